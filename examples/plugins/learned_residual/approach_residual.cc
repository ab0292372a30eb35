#include "approach_residual.h"

#include <Eigen/Cholesky>

namespace kincal_learned {

Eigen::VectorXd ApproachFeatures(const kincal::Robot& robot, const Eigen::VectorXd& qbar,
                                 const Eigen::VectorXd* qbar_previous) {
  const Eigen::Index n = qbar.size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * n);
  x.head(n) = qbar;
  if (!qbar_previous) return x;
  const Eigen::VectorXd dq = qbar - *qbar_previous;
  if (robot.velocity_limits.size() != n) {
    x.tail(n) = dq;
    return x;
  }
  const double time = (dq.array().abs() / robot.velocity_limits.array()).maxCoeff();  // s, at full speed
  if (time > 0) x.tail(n) = dq / time;
  return x;
}

Eigen::Vector3d ApproachResidual::Residual(const kincal::Robot& robot, const Eigen::VectorXd& qbar,
                                           const Eigen::VectorXd* qbar_previous) const {
  const Eigen::VectorXd x = ApproachFeatures(robot, qbar, qbar_previous).cwiseQuotient(spread_);
  return residual_->Predict(x);
}

Eigen::VectorXd ApproachResidual::JointOffset(const kincal::Robot& robot, const Eigen::VectorXd& q_errors,
                                              const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous) const {
  const Eigen::Vector3d r_meas = robot.model().base().linear() * Residual(robot, qbar, qbar_previous);
  const Eigen::MatrixXd J = robot.model().JointJacobian(q_errors, p_tool_point_).topRows(3);
  return J.transpose() * (J * J.transpose()).ldlt().solve(r_meas);
}

}  // namespace kincal_learned
