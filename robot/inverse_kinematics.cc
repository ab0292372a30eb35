#include "robot/inverse_kinematics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "framework/damped_least_squares.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal {

namespace {

struct Descent {
  bool converged = false;
  double cost = INFINITY;  // 0.5 |weighted error|^2
  double position_error = INFINITY, orientation_error = INFINITY;
};

// The weighted error of q (rotation rows times length_scale), with the unweighted norms.
struct Evaluation {
  Vector6d r = Vector6d::Zero();
  double cost = INFINITY, position_error = INFINITY, orientation_error = INFINITY;
};
Evaluation Evaluate(const KinematicModel& model, const Eigen::Isometry3d& target, bool use_orientation,
                    const InverseKinematicsOptions& o, const Eigen::VectorXd& q) {
  Evaluation v;
  v.r = PoseError(model.ForwardKinematics(q), target);
  v.position_error = v.r.head<3>().norm();
  v.orientation_error = use_orientation ? v.r.tail<3>().norm() : 0.0;
  v.r.tail<3>() *= o.length_scale;
  v.cost = 0.5 * v.r.head(use_orientation ? 6 : 3).squaredNorm();
  return v;
}

// Levenberg-Marquardt from q (in place). The error e = PoseError(T(q), target) shrinks by J dq to first
// order; the damped step solves (J^T J + mu I) dq = J^T e. The gain ratio rho of the actual to the
// predicted decrease of the cost 0.5 |e|^2 steers mu: a step with rho > 1/4 is good enough to trust the
// model more (mu / 3), one that lowers the cost less keeps mu, one that raises it is refused and mu
// grows (x 2, 4, 8, ...). Near a singular solution the Gauss-Newton model stays fair but not good
// (rho about 0.6 measured): Nielsen's smooth rule (mu x max(1/3, 1 - (2 rho - 1)^3)) then hardly lowers
// mu, whose damping of the vanishing singular direction makes the descent crawl (error ~ k^-3.5 over
// k iterations, 800 iterations to 1e-10 m at the seed's arm stretched with its wrist singular); this rule
// converges there in about 35.
Descent Descend(const Robot& robot, const Eigen::Isometry3d& target, bool use_orientation,
                const InverseKinematicsOptions& o, Eigen::VectorXd* q, int* iterations) {
  const KinematicModel& model = robot.model();
  const int rows = use_orientation ? 6 : 3, n = static_cast<int>(q->size());
  Evaluation current = Evaluate(model, target, use_orientation, o, *q);
  double mu = -1.0, nu = 2.0;
  double mark_cost = current.cost;  // the cost when it last halved
  int mark = 0;
  Descent d;
  DampedNormalEquations<Eigen::Dynamic> normal;  // reused: no allocation per iteration
  for (int it = 0;; ++it) {
    d.cost = current.cost;
    d.position_error = current.position_error;
    d.orientation_error = current.orientation_error;
    if (d.position_error < o.position_tolerance && d.orientation_error < o.orientation_tolerance) {
      d.converged = true;
      return d;
    }
    if (it >= o.max_iterations || it - mark >= o.stall_iterations) return d;
    ++*iterations;
    Matrix6Xd J = model.JointJacobian(*q);
    J.bottomRows<3>() *= o.length_scale;
    normal.Assemble(J.topRows(rows), current.r.head(rows));
    const double scale = std::max(normal.H().diagonal().maxCoeff(), 1e-300);
    if (mu < 0) mu = o.damping * scale;
    // More damping until a step lowers the cost; none does once the damping dwarfs J^T J (a minimum).
    bool accepted = false;
    while (!accepted && mu < 1e12 * scale) {
      // A damped system that is not positive definite to rounding counts as a refused step.
      const bool factored = normal.Factor(mu);
      const Eigen::VectorXd step = factored ? normal.Step() : Eigen::VectorXd::Zero(n).eval();
      double fit2 = 0.0;  // |J step|^2
      for (int i = 0; i < rows; ++i) fit2 += std::pow(J.row(i).dot(step), 2);
      const double predicted = step.dot(normal.g()) - 0.5 * fit2;
      const Evaluation trial =
          factored && step.allFinite() ? Evaluate(model, target, use_orientation, o, *q + step) : Evaluation();
      if (trial.cost < current.cost && predicted > 0) {
        const double rho = (current.cost - trial.cost) / predicted;
        if (rho > 0.25) mu = std::max(mu / 3, 1e-20 * scale);  // a floor keeps mu * nu growing
        nu = 2.0;
        *q += step;
        current = trial;
        accepted = true;
      } else {
        mu *= nu;
        nu *= 2;
      }
    }
    if (!accepted) return d;
    if (current.cost < 0.5 * mark_cost) {
      mark_cost = current.cost;
      mark = it + 1;
    }
  }
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
  for (int start = 0; start <= options.restarts; ++start) {
    Eigen::VectorXd q(n);
    if (start == 0 && initial.size() == n && initial.allFinite()) {
      q = initial;
    } else {
      for (int j = 0; j < n; ++j) {
        const auto [low, high] = robot.Limit(j);
        q[j] = start == 0 ? 0.5 * (low + high) : rng.Uniform(low, high);
      }
    }
    ++result.starts;
    Descent d = Descend(robot, T_meas_tool, use_orientation, options, &q, &result.iterations);
    if (!q.allFinite()) continue;
    bool clamped = false;
    // Whole turns into the limits, nearest the descent's result; on a limit to rounding: onto it.
    const bool inside = WrapIntoLimits(robot, nullptr, q, 1e-9, &clamped);
    if (clamped) {
      // On a limit: the errors of the joints as returned.
      const Evaluation e = Evaluate(robot.model(), T_meas_tool, use_orientation, options, q);
      d.cost = e.cost;
      d.position_error = e.position_error;
      d.orientation_error = e.orientation_error;
      d.converged =
          d.position_error < options.position_tolerance && d.orientation_error < options.orientation_tolerance;
    }
    // Preference: converged inside the limits, then converged outside, then the least cost.
    const bool better = d.converged ? (!result.converged || (inside && !result.within_limits))
                                    : (!result.converged && d.cost < best_cost);
    if (better) {
      best = q;
      best_cost = d.cost;
      result.converged = d.converged;
      result.within_limits = inside;
      result.position_error = d.position_error;
      result.orientation_error = d.orientation_error;
    }
    if (d.converged && inside) break;
  }
  result.q = best.size() == n ? best : Eigen::VectorXd::Zero(n);
  return result;
}

}  // namespace kincal
