#include "programs/configuration.h"

#include <cmath>
#include <stdexcept>

#include "framework/units.h"

namespace kincal {
namespace {


// Signs of the two arm criteria at q: (wrist centre in front of axis 1, wrist centre on the positive side
// of the line through axes 2 and 3), from the joint axes as the Jacobian gives them.
Eigen::Vector2d ArmSides(const Robot& robot, const Eigen::VectorXd& q) {
  const KinematicModel& model = robot.model();
  const Matrix6Xd J = model.JointJacobian(q);
  const Eigen::Vector3d p = model.ForwardKinematics(q).translation();
  Eigen::Vector3d w[6], a[6];
  for (int j = 0; j < 6; ++j) {
    w[j] = J.col(j).tail<3>().normalized();
    a[j] = p + w[j].cross(J.col(j).head<3>());  // the foot of the perpendicular from p on axis j
  }
  // The wrist centre: the point of axis 5 nearest axis 4 (where they meet). a[4] is that point only when
  // the tool point lies in the plane through it normal to axis 5 (no tool offset along axis 5).
  Eigen::Vector3d wrist = a[3];
  const Eigen::Vector3d n = w[4].cross(w[3]);
  if (n.squaredNorm() > 1e-18) {
    const double t = (a[3] - a[4]).cross(w[3]).dot(n) / n.squaredNorm();
    wrist = a[4] + t * w[4];
  }
  return {(wrist - a[0]).dot(w[1].cross(w[0])), (a[2] - a[1]).cross(wrist - a[1]).dot(w[1])};
}

void Check(const Robot& robot) {
  bool ok = robot.dof() == 6;
  for (int j = 0; ok && j < 6; ++j) ok = robot.model().joint_type(j) == JointType::kRevolute;
  if (!ok) throw std::invalid_argument("configuration fields need a robot with 6 revolute joints");
}

int Quadrant(double q) { return static_cast<int>(std::floor(q / (90 * kDegree) + 1e-12)); }

// The per-joint part of a configuration: whether joint j at `angle` agrees with it.
bool JointAgrees(ConfigurationConvention convention, const std::vector<int>& c, int j, double angle) {
  if (convention == ConfigurationConvention::kAbb) {
    const int index = j == 0 ? 0 : j == 3 ? 1 : j == 5 ? 2 : -1;
    return index < 0 || Quadrant(angle) == c[index];
  }
  if (convention == ConfigurationConvention::kKuka) return ((c[1] >> j) & 1) == (angle < 0 ? 1 : 0);
  return true;
}

}  // namespace

ConfigurationRules::ConfigurationRules(ConfigurationConvention convention, const Robot& controller)
    : convention_(convention), controller_(&controller) {
  if (convention == ConfigurationConvention::kNone) return;
  Check(controller);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  const Eigen::Vector2d zero = ArmSides(controller, q);
  zero_front_ = zero[0];
  zero_side_ = zero[1];
  q[1] = -90 * kDegree;
  q[2] = 90 * kDegree;
  home_side_ = ArmSides(controller, q)[1];
}

std::vector<int> ConfigurationRules::Of(const Eigen::VectorXd& q) const {
  if (convention_ == ConfigurationConvention::kNone) return {};
  const Eigen::Vector2d sides = ArmSides(*controller_, q);
  const bool negative5 = std::remainder(q[4], 2 * M_PI) < 0;
  if (convention_ == ConfigurationConvention::kAbb) {
    const bool behind1 = (sides[0] < 0) != (zero_front_ < 0);
    const bool behind_lower = (sides[1] < 0) != (zero_side_ < 0);
    return {Quadrant(q[0]), Quadrant(q[3]), Quadrant(q[5]), 4 * behind1 + 2 * behind_lower + negative5};
  }
  const int status = ((sides[0] < 0) != (zero_front_ < 0) ? 1 : 0) + ((sides[1] < 0) == (home_side_ < 0) ? 2 : 0) +
                     (negative5 ? 4 : 0);
  int turn = 0;
  for (int j = 0; j < 6; ++j) turn |= (q[j] < 0 ? 1 : 0) << j;
  return {status, turn};
}

bool ConfigurationRules::Fit(const Eigen::VectorXd& q_in, const std::vector<int>& configuration,
                             const Eigen::VectorXd& reference, Eigen::VectorXd* q) const {
  const int n = controller_->dof();
  *q = q_in;
  for (int j = 0; j < n; ++j) {
    const auto [low, high] = controller_->Limit(j);
    double chosen = NAN, distance = INFINITY;
    for (int k = -3; k <= 3; ++k) {
      const double angle = q_in[j] + 2 * M_PI * k;
      if (angle < low - 1e-9 || angle > high + 1e-9) continue;
      if (!JointAgrees(convention_, configuration, j, angle)) continue;
      if (std::abs(angle - reference[j]) < distance) {
        distance = std::abs(angle - reference[j]);
        chosen = angle;
      }
    }
    if (!std::isfinite(chosen)) return false;
    (*q)[j] = chosen;
  }
  return Of(*q) == configuration;
}

ConfigurationRules::Solution ConfigurationRules::Solve(const NominalInverseKinematics& ik,
                                                       const Eigen::Isometry3d& T_meas_tool,
                                                       const std::vector<int>& configuration,
                                                       const Eigen::VectorXd& reference) const {
  Solution out;
  const int n = controller_->dof();
  Eigen::VectorXd ref = reference;
  if (ref.size() != n) {  // the middle of the limits, as the inverse kinematics takes it
    ref.resize(n);
    for (int j = 0; j < n; ++j) ref[j] = 0.5 * (controller_->Limit(j).first + controller_->Limit(j).second);
  }
  const IkSolution nearest = ik.Solve(T_meas_tool, ref);
  const bool reached = nearest.status == IkStatus::kSolved || nearest.status == IkStatus::kSingular;
  if (convention_ == ConfigurationConvention::kNone || configuration.empty()) {
    out.q = nearest.q;
    out.found = reached;
    return out;
  }
  Eigen::VectorXd q;
  if (reached && Fit(nearest.q, configuration, ref, &q)) return {q, true};
  double best = INFINITY;
  for (const IkSolution& s : ik.AllBranches(T_meas_tool, ref)) {
    if (!Fit(s.q, configuration, ref, &q)) continue;
    const double d = (q - ref).squaredNorm();
    if (d < best) {
      best = d;
      out.q = q;
      out.found = true;
    }
  }
  return out;
}

}  // namespace kincal
