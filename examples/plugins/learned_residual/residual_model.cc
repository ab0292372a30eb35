#include "residual_model.h"

namespace kincal_learned {

ResidualModel::ResidualModel(std::unique_ptr<kincal::KinematicModel> inner, std::shared_ptr<const KernelRidge> residual,
                             bool in_tool_frame)
    : inner_(std::move(inner)), residual_(std::move(residual)), in_tool_frame_(in_tool_frame) {
  std::vector<kincal::JointType> types;
  for (int i = 0; i < inner_->dof(); ++i) types.push_back(inner_->joint_type(i));
  Declare(types, inner_->parameter_info());
  const std::vector<bool> mask = inner_->FreeMask();
  SetParameters(inner_->Parameters());
  SetFreeMask(mask);
}

std::unique_ptr<kincal::KinematicModel> ResidualModel::Clone() const {
  auto copy = std::make_unique<ResidualModel>(inner_->Clone(), residual_, in_tool_frame_);
  copy->SetFreeMask(FreeMask());
  return copy;
}

Eigen::Isometry3d ResidualModel::ForwardKinematics(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d T = inner_->ForwardKinematics(q);
  T.translation() += in_tool_frame_ ? Eigen::Vector3d(T.linear() * residual_->Predict(q)) : residual_->Predict(q);
  return T;
}

std::vector<Eigen::Isometry3d> ResidualModel::FramePoses(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> poses = inner_->FramePoses(q);
  const Eigen::Matrix3d R = poses.back().linear();
  poses.back().translation() += in_tool_frame_ ? Eigen::Vector3d(R * residual_->Predict(q)) : residual_->Predict(q);  // the tool; the joint frames stay the geometry's
  return poses;
}

kincal::Matrix6Xd ResidualModel::JointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point) const {
  kincal::Matrix6Xd J = inner_->JointJacobian(q, p_tool_point);
  const Eigen::MatrixXd G = residual_->Gradient(q);
  J.topRows<3>() += in_tool_frame_ ? Eigen::MatrixXd(inner_->ForwardKinematics(q).linear() * G) : G;
  return J;
}

std::vector<Eigen::Matrix4d> ResidualModel::PoseDerivatives(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Matrix4d> dT = inner_->PoseDerivatives(q);
  Eigen::MatrixXd G = residual_->Gradient(q);
  if (in_tool_frame_) G = inner_->ForwardKinematics(q).linear() * G;
  for (size_t i = 0; i < dT.size(); ++i) dT[i].block<3, 1>(0, 3) += G.col(i);
  return dT;
}

Eigen::Isometry3d ResidualModel::ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                                   kincal::Matrix6Xd* J) const {
  Eigen::Isometry3d T = inner_->ParameterJacobian(q, p_tool_point, J);
  T.translation() += in_tool_frame_ ? Eigen::Vector3d(T.linear() * residual_->Predict(q)) : residual_->Predict(q);
  return T;
}

}  // namespace kincal_learned
