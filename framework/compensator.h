#pragma once
// Compensator: given a target pose of the tool in the measurement frame and the joints the controller's
// nominal inverse kinematics gives for it (the seed), which joints must be commanded so that the real
// arm (the identified robot) reaches the target?  Prepare() once (offline tables), then Compensate() per
// target. Compensate() is the non-virtual entry point: it validates, computes a seed when the target
// has none, times, converts the desired actual angles into commands (ratios), and guarantees that no NaN
// leaves it.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/registry.h"
#include "framework/robot.h"

namespace kincal {

class NominalInverseKinematics;

enum class CompensationStatus { kConverged, kIterationLimit, kSingular, kUnreachable, kFailed };
std::string ToString(CompensationStatus status);

struct CompensationTarget {
  Eigen::Isometry3d T_meas_tool = Eigen::Isometry3d::Identity();
  bool has_orientation = true;  // false: position only (3 equations)
  Eigen::VectorXd seed;         // the controller's nominal joint solution (its readings); empty: solved here
  // The commands (readings) of the previous target of the program, which the arm comes from; empty: none.
  // Joint errors that depend on the move (backlash, approach) are inverted for that move.
  Eigen::VectorXd previous_command;
};

struct CompensationReport {
  CompensationStatus status = CompensationStatus::kFailed;
  std::string message;
  int iterations = 0;
  double position_error = NAN;     // m, identified FK of q_actual against the target
  double orientation_error = NAN;  // rad (0 for position-only targets)
  bool seed_computed = false;      // the target had no seed: nominal inverse kinematics was solved
  bool non_finite = false;         // the method returned a non-finite solution (replaced by the seed)
  double wall_time_seconds = 0.0;
  // Per iteration (the convergence plot): errors before the first step and after each step.
  std::vector<double> position_history;
  std::vector<double> orientation_history;
};

struct CompensationResult {
  Eigen::VectorXd q_actual;   // joint angles the identified robot needs
  Eigen::VectorXd q_command;  // what to command to a controller converting with the nominal ratios
  std::vector<int64_t> encoders;  // motor counts to command (when the robot has drives)
  CompensationReport report;
};

class Compensator {
 public:
  virtual ~Compensator() = default;
  virtual std::string name() const = 0;

  // Offline stage. `nominal` is what the controller believes (its IK and ratios), `identified` what the
  // arm really is. Throws std::invalid_argument if the two differ in joint count.
  void Prepare(const Robot& nominal, const Robot& identified);
  CompensationResult Compensate(const CompensationTarget& target) const;

 protected:
  const Robot& nominal() const { return nominal_; }
  const Robot& identified() const { return identified_; }
  // Iterative methods return true: a target they do not reach from the seed is retried from the nominal
  // arm's closed-form branches (RestartFromBranches). Default false (table lookups gain nothing).
  virtual bool RestartsFromBranches() const { return false; }

 private:
  virtual void DoPrepare() {}
  // Fills result->q_actual and the report's status, iterations and histories; errors are computed after.
  virtual void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                            CompensationResult* result) const = 0;

  void RestartFromBranches(const CompensationTarget& target, const Eigen::VectorXd& seed,
                           CompensationResult* result) const;

  Robot nominal_;
  Robot identified_;
  // The controller's inverse kinematics (framework/nominal_ik.h), for targets without a seed.
  std::shared_ptr<const NominalInverseKinematics> nominal_ik_;
  bool prepared_ = false;
};

using CompensatorRegistry = Registry<Compensator>;
// Every compensator kincal knows (defined in compensators/builtin.cc).
const CompensatorRegistry& Compensators();

}  // namespace kincal
