#include "residual_model.h"

namespace kincal_learned {

ResidualModel::ResidualModel(std::unique_ptr<kincal::KinematicModel> inner, std::shared_ptr<const KernelRidge> residual,
                             bool in_tool_frame, std::shared_ptr<const ApproachResidual> approach)
    : inner_(std::move(inner)),
      residual_(std::move(residual)),
      in_tool_frame_(in_tool_frame),
      approach_(std::move(approach)) {
  std::vector<kincal::JointType> types;
  for (int i = 0; i < inner_->dof(); ++i) types.push_back(inner_->joint_type(i));
  Declare(types, inner_->parameter_info());
  const std::vector<bool> mask = inner_->FreeMask();
  SetParameters(inner_->Parameters());
  SetFreeMask(mask);
}

std::unique_ptr<kincal::KinematicModel> ResidualModel::Clone() const {
  auto copy = std::make_unique<ResidualModel>(inner_->Clone(), residual_, in_tool_frame_, approach_);
  copy->SetFreeMask(FreeMask());
  return copy;
}

Eigen::Matrix3d ResidualModel::FrameRotation(const Eigen::Matrix3d& R_meas_tool) const {
  return in_tool_frame_ ? R_meas_tool : Eigen::Matrix3d(inner_->base().linear());
}

Eigen::Vector3d ResidualModel::CartesianOffset(const Eigen::VectorXd& q, const Eigen::Matrix3d& R_meas_tool) const {
  if (!residual_) return Eigen::Vector3d::Zero();
  return FrameRotation(R_meas_tool) * residual_->Predict(q);
}

Eigen::Isometry3d ResidualModel::ForwardKinematics(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d T = inner_->ForwardKinematics(q);
  T.translation() += CartesianOffset(q, T.linear());
  return T;
}

std::vector<Eigen::Isometry3d> ResidualModel::FramePoses(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> poses = inner_->FramePoses(q);
  const Eigen::Matrix3d R = poses.back().linear();
  poses.back().translation() += CartesianOffset(q, R);  // the tool; the joint frames stay the geometry's
  return poses;
}

kincal::Matrix6Xd ResidualModel::JointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point) const {
  kincal::Matrix6Xd J = inner_->JointJacobian(q, p_tool_point);
  if (!residual_) return J;
  const Eigen::Matrix3d R = FrameRotation(inner_->ForwardKinematics(q).linear());
  const Eigen::MatrixXd G = residual_->Gradient(q);
  const Eigen::Vector3d offset = R * residual_->Predict(q);
  for (int i = 0; i < J.cols(); ++i) {
    J.block<3, 1>(0, i) += R * G.col(i);
    // In the tool frame the residual turns with the tool: d(R r)/dq_i also has omega_i x (R r).
    if (in_tool_frame_) J.block<3, 1>(0, i) += J.block<3, 1>(3, i).cross(offset);
  }
  return J;
}

std::vector<Eigen::Matrix4d> ResidualModel::PoseDerivatives(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Matrix4d> dT = inner_->PoseDerivatives(q);
  if (!residual_) return dT;
  const Eigen::Matrix3d R = FrameRotation(inner_->ForwardKinematics(q).linear());
  const Eigen::MatrixXd G = residual_->Gradient(q);
  const Eigen::Vector3d r = residual_->Predict(q);
  for (size_t i = 0; i < dT.size(); ++i) {
    Eigen::Vector3d d = R * G.col(i);
    if (in_tool_frame_) d += dT[i].block<3, 3>(0, 0) * r;  // dR/dq_i r
    dT[i].block<3, 1>(0, 3) += d;
  }
  return dT;
}

Eigen::Isometry3d ResidualModel::ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                                   kincal::Matrix6Xd* J) const {
  Eigen::Isometry3d T = inner_->ParameterJacobian(q, p_tool_point, J);
  T.translation() += CartesianOffset(q, T.linear());
  return T;
}

}  // namespace kincal_learned

namespace kincal_learned {

Eigen::VectorXd ResidualModel::Offset(const kincal::Robot& robot, const Eigen::VectorXd& q_errors,
                                      const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous) const {
  if (!approach_) return Eigen::VectorXd::Zero(q_errors.size());
  return approach_->JointOffset(robot, q_errors, qbar, qbar_previous);
}

}  // namespace kincal_learned
