#pragma once
// Random reachable targets for tests, benchmarks and studies of compensators: configurations of the
// identified (real) robot uniform within the joint limits, the poses they reach, and as seeds the
// nominal robot's inverse kinematics started from the true configuration (the controller's solution in
// the same branch). Configurations are rejected when the nominal inverse kinematics does not converge,
// leaves the joint limits or lands on another branch (the controller has no solution there), or when the identified
// robot's Jacobian is too close to singular (min_sigma_ratio).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "compensators/compensator.h"

namespace kincal {

struct RandomTargetOptions {
  int count = 100;
  uint64_t seed = 1;
  bool orientation = true;  // false: position-only targets
  // Reject configurations where sigma_min / sigma_max of the identified Jacobian (position rows in units
  // of `length_scale`) is below this. 0 keeps every configuration whose nominal IK converges.
  double min_sigma_ratio = 0.0;
  double length_scale = 0.5;  // m
  // rad: a nominal solution farther than this from the true configuration (in any joint) is another
  // branch, not the controller's solution for it.
  double max_seed_distance = 0.5;
  bool IsValid(std::string* why) const;
};

struct RandomTargets {
  std::vector<CompensationTarget> targets;  // T_meas_tool and the nominal seed
  std::vector<Eigen::VectorXd> q_true;      // the identified robot's configuration for each target
  int rejected = 0;
};

// Throws std::invalid_argument for invalid options or robots that differ in joint count.
RandomTargets MakeRandomTargets(const Robot& nominal, const Robot& identified, const RandomTargetOptions& options);

// sigma_min / sigma_max of A (its min(rows, cols) singular values); 0 when A is zero.
double SingularValueRatio(const Eigen::MatrixXd& A);
// sigma_min / sigma_max of the model's Jacobian at q, position rows divided by length_scale.
double JacobianConditionRatio(const KinematicModel& model, const Eigen::VectorXd& q, double length_scale);

}  // namespace kincal
