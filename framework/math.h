#pragma once
// Rigid-transform helpers shared by every module. Frames in names: T_a_b is the pose of b in a.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kincal {

using Matrix6Xd = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

// Roll-pitch-yaw about fixed x, y, z: R = Rz(yaw) * Ry(pitch) * Rx(roll), as in URDF.
Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy);
// Inverse of RotationFromRpy; pitch in [-pi/2, pi/2]. Exact to rounding even next to gimbal lock; at exact
// lock (R(0,0) = R(1,0) = 0) roll is set to 0.
Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R);

Eigen::Isometry3d PoseFromXyzRpy(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy);

// Rotation vector (axis * angle, angle in [0, pi]) of R; accurate near 0 and near pi.
Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R);
Eigen::Matrix3d RotationExp(const Eigen::Vector3d& omega);

// Angle of R_a^T R_b in [0, pi].
double RotationAngleBetween(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b);

// 6-vector error that takes `from` to `to`: (p_to - p_from, log(R_to R_from^T)), both in the
// frame the poses are expressed in. Matches the row layout of the model Jacobians.
Vector6d PoseError(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to);

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle);

}  // namespace kincal
