#include "framework/kinematic_model.h"

#include <stdexcept>

namespace kincal {

std::vector<std::string> KinematicModel::ParameterNames() const {
  std::vector<std::string> names;
  names.reserve(info_.size());
  for (const auto& p : info_) names.push_back(p.name);
  return names;
}

void KinematicModel::SetParameters(const Eigen::VectorXd& values) {
  if (values.size() != values_.size()) {
    throw std::invalid_argument("SetParameters: expected " + std::to_string(values_.size()) + " values, got " +
                                std::to_string(values.size()));
  }
  values_ = values;
  OnParametersChanged();
}

int KinematicModel::FindParameter(const std::string& name) const {
  for (size_t i = 0; i < info_.size(); ++i) {
    if (info_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int KinematicModel::ParameterIndex(const std::string& name) const {
  const int index = FindParameter(name);
  if (index < 0) {
    std::string list;
    for (const auto& p : info_) list += (list.empty() ? "" : ", ") + p.name;
    throw std::invalid_argument("unknown parameter '" + name + "' of a " + convention() +
                                " model (expected one of: " + list + ")");
  }
  return index;
}

void KinematicModel::SetParameter(const std::string& name, double value) {
  values_[ParameterIndex(name)] = value;
  OnParametersChanged();
}

void KinematicModel::SetFreeMask(const std::vector<bool>& mask) {
  if (mask.size() != free_.size()) {
    throw std::invalid_argument("SetFreeMask: expected " + std::to_string(free_.size()) + " flags");
  }
  free_ = mask;
}

Eigen::Isometry3d KinematicModel::base() const {
  return PoseFromXyzRpy(values_.segment<3>(base_index_), values_.segment<3>(base_index_ + 3));
}

Eigen::Isometry3d KinematicModel::tool() const {
  return PoseFromXyzRpy(values_.segment<3>(tool_index_), values_.segment<3>(tool_index_ + 3));
}

void KinematicModel::SetBase(const Eigen::Isometry3d& T_meas_base) {
  values_.segment<3>(base_index_) = T_meas_base.translation();
  values_.segment<3>(base_index_ + 3) = RpyFromRotation(T_meas_base.linear());
  OnParametersChanged();
}

void KinematicModel::SetTool(const Eigen::Isometry3d& T_n_tool) {
  values_.segment<3>(tool_index_) = T_n_tool.translation();
  values_.segment<3>(tool_index_ + 3) = RpyFromRotation(T_n_tool.linear());
  OnParametersChanged();
}

Matrix6Xd KinematicModel::ParameterJacobian(const Eigen::VectorXd& q) const {
  Matrix6Xd J;
  ParameterJacobian(q, Eigen::Vector3d::Zero(), &J);
  return J;
}

void KinematicModel::Declare(std::vector<JointType> joint_types, std::vector<ParameterInfo> info) {
  joint_types_ = std::move(joint_types);
  info_ = std::move(info);
  values_ = Eigen::VectorXd::Zero(static_cast<int>(info_.size()));
  free_.assign(info_.size(), true);
  base_index_ = FindParameter("base_x");
  tool_index_ = FindParameter("tool_x");
  if (base_index_ < 0 || tool_index_ < 0) {
    throw std::logic_error("a kinematic model must declare base_x.. and tool_x.. parameters");
  }
}

}  // namespace kincal
