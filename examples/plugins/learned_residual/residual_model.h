#pragma once
// A kinematic model plus a learned position residual: T_meas_tool(q) = Translation(R_meas_base r(q)) *
// T_inner(q), the residual in the robot's base frame (or Translation(R_meas_tool(q) r(q)) * T_inner(q), in
// the tool frame: both move with the session bases, which transform the whole pose),
// with r a kernel ridge regression on the joint angles (kernel_ridge.h). Wrapped into the identified
// robot, it is what every kincal piece sees: predictions and held-out scores include the residual, and
// the compensators that solve the identified arm's forward kinematics (jacobian, analytic_derivative)
// invert model plus residual. The parameters are the inner model's (an estimator after this one refines
// the geometry under a fixed residual); the residual does not depend on them, so the parameter Jacobian is
// the inner model's, and the joint Jacobian adds the residual's derivative to the position rows.
// Either residual may be absent: the one on the joint angles (null: the inner pose as is), and the one on
// the readings and approach speeds (approach_residual.h), which a forward kinematics cannot see and which
// this model carries as a joint-level correction (robot/joint_readings.h applies it to the joint angles).
#include <memory>
#include <string>
#include <vector>

#include "framework/kinematic_model.h"
#include "approach_residual.h"
#include "kernel_ridge.h"
#include "robot/joint_readings.h"

namespace kincal_learned {

class ResidualModel final : public kincal::KinematicModel, public kincal::JointCorrection {
 public:
  // in_tool_frame: the regression predicts the residual in the tool frame of the inner model (rotated into
  // the measurement frame by its orientation at q), else in its base frame.
  ResidualModel(std::unique_ptr<kincal::KinematicModel> inner, std::shared_ptr<const KernelRidge> residual,
                bool in_tool_frame, std::shared_ptr<const ApproachResidual> approach = nullptr);
  std::unique_ptr<kincal::KinematicModel> Clone() const override;
  // The inner model's: robot files and the nominal inverse kinematics see that geometry (a robot file
  // written from this model keeps the geometry and loses the residual).
  std::string convention() const override { return inner_->convention(); }
  std::vector<std::string> RowKeys() const override { return inner_->RowKeys(); }
  int JointAxisFrame(int joint) const override { return inner_->JointAxisFrame(joint); }

  Eigen::Isometry3d ForwardKinematics(const Eigen::VectorXd& q) const override;
  std::vector<Eigen::Isometry3d> FramePoses(const Eigen::VectorXd& q) const override;
  kincal::Matrix6Xd JointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point) const override;
  std::vector<Eigen::Matrix4d> PoseDerivatives(const Eigen::VectorXd& q) const override;
  Eigen::Isometry3d ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                      kincal::Matrix6Xd* J) const override;
  using kincal::KinematicModel::ParameterJacobian;

  // The approach residual's joint offsets (zero without one).
  Eigen::VectorXd Offset(const kincal::Robot& robot, const Eigen::VectorXd& q_errors, const Eigen::VectorXd& qbar,
                         const Eigen::VectorXd* qbar_previous) const override;

  const KernelRidge& residual() const { return *residual_; }
  const ApproachResidual* approach() const { return approach_.get(); }

 private:
  void OnParametersChanged() override { inner_->SetParameters(Parameters()); }
  // The residual at q in the measurement frame, given the inner pose's rotation there.
  Eigen::Vector3d CartesianOffset(const Eigen::VectorXd& q, const Eigen::Matrix3d& R_meas_tool) const;
  // The rotation that takes the regression's frame to the measurement frame.
  Eigen::Matrix3d FrameRotation(const Eigen::Matrix3d& R_meas_tool) const;

  std::unique_ptr<kincal::KinematicModel> inner_;
  std::shared_ptr<const KernelRidge> residual_;
  bool in_tool_frame_ = false;
  std::shared_ptr<const ApproachResidual> approach_;
};

}  // namespace kincal_learned
