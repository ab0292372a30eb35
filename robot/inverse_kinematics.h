#pragma once
// Numerical inverse kinematics of a model, for targets that carry no controller solution and arms without
// a closed form: Levenberg-Marquardt on the 6-D pose error (position and rotation log), restarted from
// deterministic random configurations within the joint limits until one converges within the limits.
//
// Each descent runs free of the limits: clamping every step into them traps it against a limit, and
// fewer reachable poses are found for the same number of restarts. Its damping follows the gain ratio (shrink after a good step, double, quadruple ... after
// a refused one), which lets it converge at singular configurations, where a fixed damping stalls. A
// descent ends at convergence, when its cost has not halved in `stall_iterations` iterations (a local
// minimum or a crawl: restarting is cheaper), or at `max_iterations`. Its result is moved into the
// limits by whole turns of revolute joints (a joint within 1e-9 outside a limit is clamped onto it);
// further starts run only while none has converged inside the limits, and a solution that exists only
// outside them is returned with within_limits = false.
#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/options.h"
#include "robot/robot.h"

namespace kincal {

struct InverseKinematicsOptions {
  int max_iterations = 100;              // per start, at most
  int stall_iterations = 12;             // a start ends when its cost has not halved in this many iterations
  int restarts = 100;                    // further starts after the first (only while none converged)
  double position_tolerance = 1e-10;     // m
  double orientation_tolerance = 1e-10;  // rad
  double damping = 1e-6;                 // initial damping, relative to the largest diagonal entry of J^T J
  double length_scale = 1.0;             // m per rad: weight of rotation against position
  uint64_t seed = 1;
  // Reading (a map of these keys, e.g. NominalIkOptions' `numeric`), IsValid and the documentation.
  static const OptionTable<InverseKinematicsOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct InverseKinematicsResult {
  Eigen::VectorXd q;
  bool converged = false;
  bool within_limits = false;
  int iterations = 0;  // over all starts
  int starts = 0;
  double position_error = NAN;
  double orientation_error = NAN;
};

// Starts from `initial` (or the middle of the limits when empty).
InverseKinematicsResult SolveInverseKinematics(const Robot& robot, const Eigen::Isometry3d& T_meas_tool,
                                               bool use_orientation, const Eigen::VectorXd& initial,
                                               const InverseKinematicsOptions& options);

}  // namespace kincal
