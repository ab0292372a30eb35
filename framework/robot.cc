#include "framework/robot.h"

#include <stdexcept>

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

Eigen::Vector3d Robot::MarkerPosition(const std::string& id) const {
  if (id.empty()) return Eigen::Vector3d::Zero();
  const auto it = markers.find(id);
  if (it == markers.end()) {
    throw std::invalid_argument("robot '" + name + "' has no marker '" + id + "' (add it under `markers:`)");
  }
  return it->second;
}

Eigen::Isometry3d Robot::SessionBase(int session) const {
  const auto it = session_bases.find(session);
  return it == session_bases.end() ? model_->base() : it->second;
}

}  // namespace kincal
