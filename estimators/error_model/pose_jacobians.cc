#include "estimators/error_model/pose_jacobians.h"

#include <cmath>

namespace kincal {

Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi) {
  const double t = phi.norm();
  const Eigen::Matrix3d K = Skew(phi);
  double c;
  if (t < 1e-4) {
    // 1/t^2 - (1 + cos t) / (2 t sin t) = 1/12 + t^2/720 + O(t^4).
    c = 1.0 / 12.0 + t * t / 720.0;
  } else {
    c = 1.0 / (t * t) - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t));
  }
  return Eigen::Matrix3d::Identity() - 0.5 * K + c * K * K;
}

Matrix6d PoseParameterJacobian(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy, const Eigen::Vector3d& p) {
  const double pitch = rpy[1], yaw = rpy[2];  // the roll axis does not depend on roll
  // Rotation axes in the outer frame: yaw about z, pitch about Rz(yaw) y, roll about Rz(yaw) Ry(pitch) x.
  const Eigen::Vector3d w_yaw = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d w_pitch(-std::sin(yaw), std::cos(yaw), 0.0);
  const Eigen::Vector3d w_roll(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), -std::sin(pitch));
  const Eigen::Vector3d arm = p - xyz;
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>().setIdentity();
  const Eigen::Vector3d axes[3] = {w_roll, w_pitch, w_yaw};
  for (int k = 0; k < 3; ++k) {
    J.col(3 + k).head<3>() = axes[k].cross(arm);
    J.col(3 + k).tail<3>() = axes[k];
  }
  return J;
}

Vector6d XyzRpyFromPose(const Eigen::Isometry3d& T) {
  Vector6d v;
  v.head<3>() = T.translation();
  v.tail<3>() = RpyFromRotation(T.linear());
  return v;
}

}  // namespace kincal
