#include "robot/robot.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "framework/svd.h"

namespace kincal {

Robot::Robot(std::string robot_name, std::unique_ptr<KinematicModel> model)
    : name(std::move(robot_name)), model_(ModelPtr(std::move(model))) {}

Robot Robot::WithModel(std::unique_ptr<KinematicModel> model) const {
  Robot out = *this;
  out.model_ = ModelPtr(std::move(model));
  return out;
}

std::pair<double, double> Robot::Limit(int joint) const {
  if (limits.empty()) return {-M_PI / 2, M_PI / 2};
  return limits.at(joint);
}

bool WrapIntoLimits(const Robot& robot, const Eigen::VectorXd* reference, Eigen::Ref<Eigen::VectorXd> q, double slack,
                    bool* clamped) {
  constexpr double kTurn = 2 * M_PI;
  bool inside = true;
  for (int j = 0; j < q.size(); ++j) {
    const auto [low, high] = robot.Limit(j);
    double& v = q[j];
    const bool revolute = robot.model().joint_type(j) == JointType::kRevolute;
    const double ref = reference ? (*reference)[j] : v;
    // The common case, first (a compensator calls this per target): inside, and the reference within
    // half a turn.
    if (v >= low && v <= high && (!revolute || std::abs(ref - v) < 0.5 * kTurn)) continue;
    if (revolute) {
      const double k_low = std::ceil((low - slack - v) / kTurn), k_high = std::floor((high + slack - v) / kTurn);
      if (k_low <= k_high) {
        v += kTurn * std::clamp(std::round((ref - v) / kTurn), k_low, k_high);
      } else {
        const double below = v + kTurn * (k_low - 1), above = v + kTurn * k_low;
        v = (low - below) < (above - high) ? below : above;
      }
    }
    if ((v < low && v >= low - slack) || (v > high && v <= high + slack)) {
      v = std::clamp(v, low, high);
      if (clamped) *clamped = true;
    }
    inside = inside && v >= low && v <= high;
  }
  return inside;
}

Eigen::Vector3d Robot::MarkerPosition(const std::string& id) const {
  if (id.empty()) return Eigen::Vector3d::Zero();
  const auto it = markers.find(id);
  if (it == markers.end()) {
    throw std::invalid_argument("robot '" + name + "' has no marker '" + id + "' (add it under `markers:`)");
  }
  return it->second;
}

Eigen::Vector3d Robot::GravityDirection() const {
  return gravity ? gravity->normalized() : Eigen::Vector3d(-Eigen::Vector3d::UnitZ());
}

void Robot::ValidateJointLevel() const {
  const int n = dof();
  if (coupling.size() != 0) {
    if (coupling.rows() != n || coupling.cols() != n) {
      throw std::invalid_argument("coupling: expected " + std::to_string(n) + " rows of " + std::to_string(n) +
                                  " numbers");
    }
    if (!coupling.allFinite()) throw std::invalid_argument("coupling: expected finite numbers");
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(coupling);
    const Eigen::VectorXd sv = svd.singularValues();
    if (!(sv[n - 1] > 1e-9 * sv[0])) {
      throw std::invalid_argument("coupling: the matrix is singular (readings must determine the joints)");
    }
  }
  if (velocity_limits.size() != 0) {
    if (velocity_limits.size() != n)
      throw std::invalid_argument("velocity_limits: expected " + std::to_string(n) + " numbers");
    for (int i = 0; i < n; ++i) {
      if (!(velocity_limits[i] > 0.0) || !std::isfinite(velocity_limits[i])) {
        throw std::invalid_argument("velocity_limits: expected positive finite numbers");
      }
    }
  }
  if (gravity && (!gravity->allFinite() || !(gravity->norm() > 0.0) || !std::isfinite(gravity->norm()))) {
    throw std::invalid_argument("gravity: expected a non-zero direction [gx, gy, gz]");
  }
  if (joint_errors.uses_velocity_limits() && velocity_limits.size() == 0) {
    throw std::invalid_argument("joint_errors: approach terms need velocity_limits (one per joint)");
  }
  for (const auto& t : joint_errors.terms) {
    if (t.keys.size() != static_cast<size_t>(t.coefficients.size()) || !t.coefficients.allFinite()) {
      throw std::invalid_argument("joint_errors: coefficients not bound to the model or not finite");
    }
  }
}

Eigen::Isometry3d Robot::SessionBase(int session) const {
  const auto it = session_bases.find(session);
  return it == session_bases.end() ? model_->base() : it->second;
}

}  // namespace kincal
