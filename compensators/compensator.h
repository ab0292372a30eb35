#pragma once
// Compensator: given a target pose of the tool in the measurement frame and the joints the controller's
// nominal inverse kinematics gives for it (the seed), which joints must be commanded so that the real
// arm (the identified robot) reaches the target?  Prepare() once (offline tables), then Compensate() per
// target. Compensate() is the non-virtual entry point: it validates, computes a seed when the target
// has none, times, converts the desired actual angles into commands (ratios), and guarantees that no NaN
// leaves it.
//
// The frame contract (every compensator, the nominal inverse kinematics they seed from, `kincal
// compensate` and `kincal filter` follow it; the studies' compensators too, while their validation seeds
// are still the nominal file's own inverse kinematics, studies/validation.cc):
//  - Targets are poses of the tool in the measurement frame (the tracker's), T_meas_tool. A caller whose
//    targets are in the robot's base frame (a robot program, `--frame base`) moves them by the
//    controller's base: T_meas_tool = T_meas_base * T_base_tool (TargetFromBaseFrame below).
//  - The identified robot is the arm as calibrated, in the measurement frame: its base T_meas_base and
//    tool T_flange_tool are the ones the calibration registered.
//  - The controller is the nominal file's joint geometry placed by that base and tool:
//        T_meas_tool^controller(q) = T_meas_base * T_base_flange^nominal(q) * T_flange_tool
//    (ControllerRobot below). A nominal file says otherwise by giving a base or a tool of its own (not
//    the identity): that one is the controller's (a cell whose work object and tool data were set up
//    from another measurement). Nominal files describe the arm alone (base and tool identity), so by
//    default the controller stands where the calibration found the arm. Prepare() applies this: nominal()
//    below, the seeds computed for targets without one and the branch restarts all use the controller.
//  - A seed (the controller's joint solution) is therefore the controller's inverse kinematics of the
//    target in this frame; a joint target (`filter`) is a seed.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/registry.h"
#include "robot/robot.h"

namespace kincal {

class NominalInverseKinematics;

// kOutOfLimits: the target is reached, but only with joints outside the identified arm's limits (q_actual
// is that solution, revolute joints moved by whole turns as near the limits as they go).
enum class CompensationStatus { kConverged, kIterationLimit, kSingular, kUnreachable, kOutOfLimits, kFailed };
std::string ToString(CompensationStatus status);

struct CompensationTarget {
  Eigen::Isometry3d T_meas_tool = Eigen::Isometry3d::Identity();
  bool has_orientation = true;  // false: position only (3 equations)
  Eigen::VectorXd seed;         // the controller's nominal joint solution (its readings); empty: solved here
  // The commands (readings) of the previous target of the program, which the arm comes from; empty: none.
  // Joint errors that depend on the move (backlash, approach) are inverted for that move.
  Eigen::VectorXd previous_command;
};

// How Compensate() retries a target that an iterative method does not reach from the seed. Next to a
// singular configuration the identified arm's solution can lie on the other side of it (the nominal
// arm's branches meet there, the identified arm's do not at the same place), or, next to a fold of the
// nominal workspace, not exist on the controller's branch at all while another branch reaches it.
struct BranchRestartOptions {
  // Retry from the nominal arm's closed-form branches of the target and of the target moved by the pose
  // error at the seed (every side of the singular surfaces), the starts nearest the seed first.
  bool enabled = true;
  // rad: a solution within this distance of the seed in every joint is the controller's configuration.
  double same_branch_distance = 0.5;
  // When no start reaches the target on the controller's branch, take a solution on another branch that
  // lies inside the identified arm's joint limits (the one nearest the seed among those found); the
  // report says so (branch_changed). false: such targets keep the best result on the controller's branch.
  bool other_branches = true;
  // Then, when neither the seed nor the branches reach the target (a target that the nominal arm does not
  // reach at all, next to a fold of its workspace, gives no branches), starts drawn at random: the first
  // half around the seed with a spread growing to pi, the rest uniform within the joint limits (TRAC-IK's
  // random restarts). A fixed stream: the same target gives the same joints. 0: none.
  int random_starts = 64;
  // Keys `branch_restarts` (enabled), `same_branch_distance`, `other_branches`, `random_starts`.
  static const OptionTable<BranchRestartOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct CompensationReport {
  CompensationStatus status = CompensationStatus::kFailed;
  std::string message;
  int iterations = 0;              // of the run that gave q_actual (the histories' length - 1)
  int restarts = 0;                // further starts tried after the seed (BranchRestartOptions)
  int total_iterations = 0;        // over the seed's run and every restart
  double position_error = NAN;     // m, identified FK of q_actual against the target
  double orientation_error = NAN;  // rad (0 for position-only targets)
  bool seed_computed = false;      // the target had no seed: nominal inverse kinematics was solved
  bool non_finite = false;         // the method returned a non-finite solution (replaced by the seed)
  // The target was reached on another branch than the controller's (BranchRestartOptions).
  bool branch_changed = false;
  double wall_time_seconds = 0.0;
  // Per iteration (the convergence plot): errors before the first step and after each step.
  std::vector<double> position_history;
  std::vector<double> orientation_history;
};

struct CompensationResult {
  Eigen::VectorXd q_actual;       // joint angles the identified robot needs
  Eigen::VectorXd q_command;      // what to command to a controller converting with the nominal ratios
  std::vector<int64_t> encoders;  // motor counts to command (when the robot has drives)
  CompensationReport report;
};

class Compensator {
 public:
  virtual ~Compensator() = default;
  virtual std::string name() const = 0;

  // Offline stage. `nominal` is what the controller believes (its IK and ratios), `identified` what the
  // arm really is; the controller is ControllerRobot(nominal, identified) (the frame contract). Throws
  // std::invalid_argument if the two differ in joint count.
  void Prepare(const Robot& nominal, const Robot& identified);
  CompensationResult Compensate(const CompensationTarget& target) const;

 protected:
  // The controller: ControllerRobot(nominal, identified) of Prepare().
  const Robot& nominal() const { return nominal_; }
  const Robot& identified() const { return identified_; }
  // Iterative methods return their restart options: a target they do not reach from the seed is retried
  // from the nominal arm's closed-form branches and random starts (Restart). Default none (table lookups
  // gain nothing).
  virtual const BranchRestartOptions* branch_restarts() const { return nullptr; }
  // Called once the report holds the identified robot's errors at q_actual (its forward kinematics,
  // computed once by Compensate()): a method whose status depends on them (a fixed number of steps)
  // sets it here. Default: the status DoCompensate() gave stands.
  virtual void JudgeErrors(const CompensationTarget& /*target*/, CompensationResult* /*result*/) const {}

 private:
  virtual void DoPrepare() {}
  // Fills result->q_actual and the report's status, iterations and histories; errors are computed after.
  virtual void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                            CompensationResult* result) const = 0;

  // Retries from the nominal closed-form branches, then from random starts (BranchRestartOptions).
  void Restart(const CompensationTarget& target, const Eigen::VectorXd& seed, const BranchRestartOptions& options,
               CompensationResult* result) const;

  Robot nominal_;
  Robot identified_;
  // The controller's inverse kinematics (robot/nominal_ik.h), for targets without a seed.
  std::shared_ptr<const NominalInverseKinematics> nominal_ik_;
  bool prepared_ = false;
};

// The controller of the frame contract (top of this file): `nominal` with, for each of base and tool that
// it gives as the identity, the identified robot's. Everything else (joints, limits, drives) is the
// nominal file's.
Robot ControllerRobot(const Robot& nominal, const Robot& identified);
// T_meas_tool of a target given in the robot's base frame, the controller's base.
Eigen::Isometry3d TargetFromBaseFrame(const Robot& controller, const Eigen::Isometry3d& T_base_tool);

using CompensatorRegistry = Registry<Compensator>;
// Every compensator kincal knows (defined in compensators/builtin.cc).
const CompensatorRegistry& Compensators();

}  // namespace kincal
