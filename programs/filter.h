#pragma once
// Filtering a robot program (RoboDK's FilterProgram, done offline): every Cartesian target is replaced
// by the one the nominal controller must be given so that the identified arm reaches the original, and
// every joint target by the compensated joints. Per pose target, in the frame contract of
// compensators/compensator.h:
//   1. T_meas_tool = T_meas_base * T_base_frame * T_frame_tool (the controller's base, the work object);
//   2. the controller's solution on the branch the target's configuration fields name (its inverse
//      kinematics nearest the previous target's joints for formats without fields), the seed;
//   3. compensation from that seed (the previous target's commands are where the arm comes from);
//   4. the filtered pose: the controller's forward kinematics of the compensated commands, back in the
//      program's frame, with the configuration fields of those commands.
// A joint target q is the pose the controller reaches at q, compensated from q. Where the controller has
// no solution on the named branch (a target just outside the nominal arm's reach, next to a fold of its
// workspace such as the stretched elbow, that the real arm reaches), step 2 is replaced by the real arm's
// solution on that branch, found by the compensator from starts around the controller's closest attempt
// (RealArmSeed). A target that is not reached (not converged inside the joint limits, or the real arm
// has no solution on the named branch either) stays as written and is reported with file:line.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "compensators/compensator.h"
#include "framework/options.h"
#include "programs/configuration.h"
#include "programs/program.h"
#include "robot/nominal_ik.h"

namespace kincal {

struct FilterOptions {
  // The program's frame in the robot's base frame (a work object, RAPID wobjdata's uframe * oframe, a
  // KUKA BASE); identity: the targets are in the base frame.
  Eigen::Isometry3d T_base_frame = Eigen::Isometry3d::Identity();
  // The tool the targets are for, T_flange_tool; unset: the identified robot file's tool (and the
  // nominal file's, when it gives one).
  std::optional<Eigen::Isometry3d> T_flange_tool;
  // A number that moves by no more than this (relative to max(1, |value|), in the file's unit) keeps
  // its text: a program filtered with identified = nominal comes back byte for byte.
  double keep_tolerance = 1e-9;
  // Reading (`kincal filter --filter-options`: work_object and tool as [x, y, z, a, b, c] in mm and deg,
  // R = Rz(a) Ry(b) Rx(c); tool [] for the robot file's), IsValid and the documentation
  // (`kincal methods --options filter`).
  static const OptionTable<FilterOptions>& Table();
  bool IsValid(std::string* why) const;
};

// The pose [x, y, z, a, b, c] (mm, deg; R = Rz(a) Ry(b) Rx(c)) as a transform; throws
// std::invalid_argument unless there are 6 finite numbers.
Eigen::Isometry3d PoseFromXyzAbc(const std::vector<double>& xyzabc);

struct FilterReport {
  int pose_targets = 0, joint_targets = 0;
  int filtered = 0;                      // reached and written
  std::vector<std::string> not_reached;  // "path:line: why", in program order
  int branch_changed = 0;                // reached only on another branch than the named one (its fields rewritten)
  double max_position_error = 0.0, max_orientation_error = 0.0;  // m, rad: identified arm, filtered targets
};

struct FilteredProgram {
  std::string text;
  FilterReport report;
  // Per target, in program order: the compensated commands (rad), empty for targets not reached.
  std::vector<Eigen::VectorXd> commands;
};

class ProgramFilter {
 public:
  // Prepares `compensator` on (nominal, identified) with the tool of `options`. Throws
  // std::invalid_argument for invalid options or robots that do not fit.
  ProgramFilter(const Robot& nominal, const Robot& identified, std::unique_ptr<Compensator> compensator,
                const FilterOptions& options, ConfigurationConvention convention);
  FilteredProgram Filter(const ProgramFormat& format, const std::string& text, const std::string& path) const;
  const Robot& controller() const { return controller_; }

 private:
  // The commands that put the real arm on the target with joints of the named configuration, from the
  // controller's solutions on that branch of the target moved towards the shoulder by 0.1 to 30 mm, then
  // from starts around the controller's closest attempt at it (its joints moved at random with a growing
  // spread, then by whole turns onto the named fields); empty when none converges on that branch.
  Eigen::VectorXd RealArmSeed(const CompensationTarget& goal, const std::vector<int>& configuration,
                              const Eigen::VectorXd& reference) const;
  FilterOptions options_;
  Robot controller_;
  std::unique_ptr<Compensator> compensator_;
  std::unique_ptr<NominalInverseKinematics> ik_;
  std::unique_ptr<ConfigurationRules> rules_;
  Eigen::Vector3d shoulder_ = Eigen::Vector3d::Zero();  // m, measurement frame: see Shoulder in filter.cc
};

// The text with each span replaced by its new value where it moved by more than keep_tolerance.
std::string ReplaceNumbers(const std::string& text, const std::vector<NumberSpan>& spans,
                           const std::vector<double>& values, double keep_tolerance);

}  // namespace kincal
