#include "framework/inverse_kinematics.h"

#include <cmath>

#include <Eigen/Cholesky>

#include "framework/math.h"
#include "framework/random.h"

namespace kincal {

bool InverseKinematicsOptions::IsValid(std::string* why) const {
  const auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (restarts < 0) return fail("restarts must be >= 0");
  if (!(position_tolerance > 0) || !(orientation_tolerance > 0)) return fail("tolerances must be > 0");
  if (!(damping >= 0)) return fail("damping must be >= 0");
  if (!(length_scale > 0)) return fail("length_scale must be > 0");
  return true;
}

namespace {

// One damped Gauss-Newton descent from q; returns true when within tolerance.
bool Descend(const KinematicModel& model, const Eigen::Isometry3d& target, bool use_orientation,
             const InverseKinematicsOptions& o, Eigen::VectorXd* q, int* iterations, double* position_error,
             double* orientation_error) {
  const int rows = use_orientation ? 6 : 3;
  for (int it = 0; it <= o.max_iterations; ++it) {
    const Eigen::Isometry3d T = model.ForwardKinematics(*q);
    const Vector6d e = PoseError(T, target);
    *position_error = e.head<3>().norm();
    *orientation_error = use_orientation ? e.tail<3>().norm() : 0.0;
    if (*position_error < o.position_tolerance && *orientation_error < o.orientation_tolerance) return true;
    if (it == o.max_iterations) break;
    ++*iterations;
    Matrix6Xd J = model.JointJacobian(*q);
    J.bottomRows<3>() *= o.length_scale;
    Vector6d r = e;
    r.tail<3>() *= o.length_scale;
    const Eigen::MatrixXd A = J.topRows(rows);
    Eigen::MatrixXd H = A.transpose() * A;
    const double lambda = o.damping * std::max(1.0, H.diagonal().maxCoeff());
    H.diagonal().array() += lambda;
    const Eigen::VectorXd step = H.ldlt().solve(A.transpose() * r.head(rows));
    if (!step.allFinite()) return false;
    // Limit the step so that a far start does not jump across the workspace.
    const double norm = step.norm();
    *q += norm > 0.5 ? (step * (0.5 / norm)).eval() : step;
  }
  return false;
}

// Brings revolute joints into their limits by multiples of 2 pi where possible; true if all are inside.
bool WrapIntoLimits(const Robot& robot, Eigen::VectorXd* q) {
  bool inside = true;
  for (int j = 0; j < q->size(); ++j) {
    const auto [low, high] = robot.Limit(j);
    double& v = (*q)[j];
    if (robot.model().joint_type(j) == JointType::kRevolute && (v < low || v > high)) {
      const double wrapped = low + std::fmod(std::fmod(v - low, 2 * M_PI) + 2 * M_PI, 2 * M_PI);
      if (wrapped <= high) v = wrapped;
    }
    inside = inside && v >= low && v <= high;
  }
  return inside;
}

}  // namespace

InverseKinematicsResult SolveInverseKinematics(const Robot& robot, const Eigen::Isometry3d& T_meas_tool,
                                               bool use_orientation, const Eigen::VectorXd& initial,
                                               const InverseKinematicsOptions& options) {
  const int n = robot.dof();
  InverseKinematicsResult result;
  Rng rng(options.seed);
  Eigen::VectorXd best;
  double best_cost = INFINITY;
  bool best_inside = false;
  for (int start = 0; start <= options.restarts; ++start) {
    Eigen::VectorXd q(n);
    if (start == 0 && initial.size() == n) {
      q = initial;
    } else {
      for (int j = 0; j < n; ++j) {
        const auto [low, high] = robot.Limit(j);
        q[j] = start == 0 ? 0.5 * (low + high) : rng.Uniform(low, high);
      }
    }
    ++result.starts;
    double pe = INFINITY, oe = INFINITY;
    const bool ok = Descend(robot.model(), T_meas_tool, use_orientation, options, &q, &result.iterations, &pe, &oe);
    if (!q.allFinite()) continue;
    const bool inside = WrapIntoLimits(robot, &q);
    const double cost = pe + oe * options.length_scale;
    // Preference: converged inside the limits, then converged outside, then the smallest error.
    const bool better = ok ? (!result.converged || (inside && !best_inside)) : (!result.converged && cost < best_cost);
    if (better) {
      best_cost = cost;
      best = q;
      best_inside = inside;
      result.converged = ok;
      result.position_error = pe;
      result.orientation_error = oe;
    }
    if (ok && inside) break;
  }
  result.within_limits = best_inside;
  result.q = best.size() == n ? best : Eigen::VectorXd::Zero(n);
  return result;
}

}  // namespace kincal
