#include "framework/math.h"

#include <cmath>

namespace kincal {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R) {
  // R = Rz(yaw) Ry(pitch) Rx(roll). Near pitch = +-pi/2 roll and yaw are each ill-determined (only their
  // sum or difference is), so reading roll from R(2,1), R(2,2) ~ cos(pitch) would lose digits. Instead
  // yaw comes first and roll from M = Rz(-yaw) R = Ry(pitch) Rx(roll), whose entries M(1,1) = cos(roll)
  // and M(1,2) = -sin(roll) are O(1): whatever error yaw has, roll absorbs it and R comes back exact.
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cos_pitch);
  // Only at exact gimbal lock is yaw undefined; put the whole turn into it then (roll = 0).
  const double yaw = cos_pitch == 0.0 ? std::atan2(-R(0, 1), R(1, 1)) : std::atan2(R(1, 0), R(0, 0));
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double m11 = -s * R(0, 1) + c * R(1, 1);
  const double m12 = -s * R(0, 2) + c * R(1, 2);
  return {std::atan2(-m12, m11), pitch, yaw};
}

Eigen::Isometry3d PoseFromXyzRpy(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRpy(rpy);
  T.translation() = xyz;
  return T;
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  // Up to about 120 deg: vee(R - R^T) / 2 = sin(theta) k and (trace - 1) / 2 = cos(theta), so one atan2
  // gives theta to full relative precision, also for tiny angles (the compensators' steps call this
  // millions of times). Beyond, sin(theta) loses the axis: Eigen's AngleAxis through a quaternion stays
  // accurate up to pi.
  const double c = 0.5 * (R.trace() - 1.0);
  if (c > -0.5) {
    const Eigen::Vector3d v(0.5 * (R(2, 1) - R(1, 2)), 0.5 * (R(0, 2) - R(2, 0)), 0.5 * (R(1, 0) - R(0, 1)));
    const double s = v.norm();
    if (s == 0.0) return Eigen::Vector3d::Zero();
    return v * (std::atan2(s, c) / s);
  }
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
