#include "framework/math.h"

#include <cmath>

namespace kincal {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R) {
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  if (std::abs(std::abs(pitch) - M_PI / 2) < 1e-12) {
    // Gimbal lock: only yaw -+ roll is defined; put it all in yaw.
    const double yaw = std::atan2(-R(0, 1), R(1, 1));
    return {0.0, pitch, yaw};
  }
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

Eigen::Isometry3d PoseFromXyzRpy(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRpy(rpy);
  T.translation() = xyz;
  return T;
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  // Eigen's AngleAxis uses a quaternion internally, which stays accurate near 0 and pi.
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
  double angle = aa.angle();
  Eigen::Vector3d axis = aa.axis();
  if (angle > M_PI) {
    angle = 2 * M_PI - angle;
    axis = -axis;
  }
  return axis * angle;
}

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

double RotationAngleBetween(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  return RotationLog(R_a.transpose() * R_b).norm();
}

Vector6d PoseError(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to) {
  Vector6d e;
  e.head<3>() = to.translation() - from.translation();
  e.tail<3>() = RotationLog(to.linear() * from.linear().transpose());
  return e;
}

double WrapAngle(double angle) {
  double wrapped = std::remainder(angle, 2 * M_PI);
  if (wrapped <= -M_PI) wrapped += 2 * M_PI;
  return wrapped;
}

}  // namespace kincal
