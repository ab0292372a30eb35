#pragma once
// Numerical inverse kinematics of a model, for targets that carry no controller solution: damped least
// squares on the 6-D pose error (position and rotation log), restarted from deterministic random
// configurations within the joint limits until one converges within the limits. Revolute joints are
// wrapped by multiples of 2 pi into their limits where possible; a solution that stays outside them is
// returned only when no start finds one inside (within_limits = false).
#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/robot.h"

namespace kincal {

struct InverseKinematicsOptions {
  int max_iterations = 100;          // per start
  int restarts = 20;                 // further starts after the first
  double position_tolerance = 1e-10; // m
  double orientation_tolerance = 1e-10;  // rad
  double damping = 1e-6;             // added to the diagonal, scaled by the largest singular value
  double length_scale = 1.0;         // m per rad: weight of rotation against position
  uint64_t seed = 1;
  bool IsValid(std::string* why) const;
};

struct InverseKinematicsResult {
  Eigen::VectorXd q;
  bool converged = false;
  bool within_limits = false;
  int iterations = 0;      // over all starts
  int starts = 0;
  double position_error = NAN;
  double orientation_error = NAN;
};

// Starts from `initial` (or the middle of the limits when empty).
InverseKinematicsResult SolveInverseKinematics(const Robot& robot, const Eigen::Isometry3d& T_meas_tool,
                                               bool use_orientation, const Eigen::VectorXd& initial,
                                               const InverseKinematicsOptions& options);

}  // namespace kincal
