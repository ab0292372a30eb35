#pragma once
// The learned residual on the joint angles and the approach features: r(qbar, s), s_i = dq_i / max_j(|dq_j|
// / v_j) the speed of joint i on the move from the previous pose (the feature of the approach term,
// models/joint_errors.h; dq = qbar - qbar_prev, v the velocity limits; without them s = dq; without a
// previous pose or a move s = 0), each divided by its spread over the training rows. A kinematic model's
// forward kinematics sees only the actual joint angles, so this residual is a joint-level correction
// (robot/joint_readings.h, JointCorrection; ResidualModel carries it), which sees the readings and the
// move like the joint errors: the position residual
// r (in the robot's base frame) becomes the least-norm joint offsets that move the reference point (the
// marker the residual was measured at) by r to first order, dq = J^T (J J^T)^-1 R_meas_base r, J the
// point's 3 x n position Jacobian at q. r is sub-millimetre, so the neglected second order (about
// |r|^2 / reach) is below a micrometre. Compensation inverts it with the joint errors (robot/joint_readings.h,
// ReadingsFromActual).
#include <memory>

#include "kernel_ridge.h"
#include "robot/robot.h"

namespace kincal_learned {

// The regression's inputs for readings qbar after qbar_previous (null: none), before the spread scaling.
Eigen::VectorXd ApproachFeatures(const kincal::Robot& robot, const Eigen::VectorXd& qbar,
                                 const Eigen::VectorXd* qbar_previous);

class ApproachResidual {
 public:
  // residual: fitted on ApproachFeatures divided by `spread` (per column); p_tool_point: the reference
  // point in the tool frame, m.
  ApproachResidual(std::shared_ptr<const KernelRidge> residual, Eigen::VectorXd spread, Eigen::Vector3d p_tool_point)
      : residual_(std::move(residual)), spread_(std::move(spread)), p_tool_point_(p_tool_point) {}
  // The joint offsets (JointCorrection::Offset).
  Eigen::VectorXd JointOffset(const kincal::Robot& robot, const Eigen::VectorXd& q_errors, const Eigen::VectorXd& qbar,
                              const Eigen::VectorXd* qbar_previous) const;
  // The residual in the robot's base frame, m.
  Eigen::Vector3d Residual(const kincal::Robot& robot, const Eigen::VectorXd& qbar,
                           const Eigen::VectorXd* qbar_previous) const;
  const KernelRidge& residual() const { return *residual_; }

 private:
  std::shared_ptr<const KernelRidge> residual_;
  Eigen::VectorXd spread_;
  Eigen::Vector3d p_tool_point_;
};

}  // namespace kincal_learned
