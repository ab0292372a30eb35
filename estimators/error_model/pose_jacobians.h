#pragma once
// Small analytic derivatives the error model needs beyond KinematicModel's.
#include <Eigen/Core>

#include "framework/math.h"

namespace kincal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Inverse left Jacobian of SO(3) at phi: d log(Exp(delta) Exp(phi)) / d delta at delta = 0,
//   Jl^-1(phi) = I - [phi]x / 2 + (1/t^2 - (1 + cos t) / (2 t sin t)) [phi]x^2,   t = |phi|
// (Chirikjian, Stochastic Models, Information Theory and Lie Groups II, 2011, eq. 10.86; Barfoot,
// State Estimation for Robotics, eq. 7.76). It maps the angular velocity omega of R_pred to the rate of
// log(R_pred R_meas^T). Series for small t; exact to rounding for t < pi.
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi);

// Derivative of a pose parametrised as KinematicModel's base, T = Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll),
// acting on a point: columns x, y, z, roll, pitch, yaw; rows 0-2 the velocity of the transformed point
// p = T c (given: p), rows 3-5 the angular velocity of T (KinematicModel's Jacobian layout).
Matrix6d PoseParameterJacobian(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy, const Eigen::Vector3d& p);

// The parameters of such a pose: x, y, z, roll, pitch, yaw (the inverse of PoseFromXyzRpy).
Vector6d XyzRpyFromPose(const Eigen::Isometry3d& T);

}  // namespace kincal
