#include "compensators/compensator.h"

#include <chrono>
#include <algorithm>
#include <cmath>

#include "robot/nominal_ik.h"
#include "robot/joint_readings.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal {

std::string ToString(CompensationStatus status) {
  switch (status) {
    case CompensationStatus::kConverged:
      return "converged";
    case CompensationStatus::kIterationLimit:
      return "iteration_limit";
    case CompensationStatus::kSingular:
      return "singular";
    case CompensationStatus::kUnreachable:
      return "unreachable";
    case CompensationStatus::kOutOfLimits:
      return "out_of_limits";
    case CompensationStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

void Compensator::Prepare(const Robot& nominal, const Robot& identified) {
  if (!nominal.has_model() || !identified.has_model()) throw std::invalid_argument("compensate: robot without a model");
  if (nominal.dof() != identified.dof()) {
    throw std::invalid_argument("compensate: the nominal robot has " + std::to_string(nominal.dof()) +
                                " joints, the identified one " + std::to_string(identified.dof()));
  }
  if (nominal.drives.has_value() != identified.drives.has_value()) {
    throw std::invalid_argument("compensate: give drives in both robot files or in neither");
  }
  nominal_ = ControllerRobot(nominal, identified);
  identified_ = identified;
  // The controller's solution is only a seed here: where the closed form has none (a target the nominal
  // arm does not reach), one damped Newton run from the reference is enough, and the restarts that find
  // the identified arm's solution are Restart()'s, on the arm that matters.
  NominalIkOptions ik_options;
  ik_options.numeric.restarts = 0;
  nominal_ik_ = std::make_shared<const NominalInverseKinematics>(nominal_, ik_options);
  prepared_ = true;
  DoPrepare();
}

Robot ControllerRobot(const Robot& nominal, const Robot& identified) {
  Robot controller = nominal;
  const auto is_identity = [](const Eigen::Isometry3d& T) { return T.matrix() == Eigen::Matrix4d::Identity(); };
  if (is_identity(nominal.model().base())) controller.model().SetBase(identified.model().base());
  if (is_identity(nominal.model().tool())) controller.model().SetTool(identified.model().tool());
  return controller;
}

Eigen::Isometry3d TargetFromBaseFrame(const Robot& controller, const Eigen::Isometry3d& T_base_tool) {
  return controller.model().base() * T_base_tool;
}

const OptionTable<BranchRestartOptions>& BranchRestartOptions::Table() {
  using O = BranchRestartOptions;
  static const OptionTable<O> table =
      OptionTable<O>("branch restarts")
          .Add("branch_restarts", &O::enabled, "retry a missed target from the nominal arm's branches")
          .Add("same_branch_distance", &O::same_branch_distance,
               "rad: a solution this near the seed in every joint is the controller's branch", Positive())
          .Add("other_branches", &O::other_branches, "accept a solution on another branch within the limits")
          .Add("random_starts", &O::random_starts, "random starts after the branches", Within(0, 100000));
  return table;
}

bool BranchRestartOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

namespace {

double MaxJointDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).cwiseAbs().maxCoeff(); }

// The nominal arm's closed-form branches of the target moved by the pose error at the seed,
// T_nominal(seed) T_identified(seed)^-1 T_target (the pose whose nominal solution the identified arm puts
// at the target, to first order), then those of the target itself; the nearest to the seed first.
std::vector<IkSolution> BranchStarts(const NominalInverseKinematics& ik, const Robot& nominal, const Robot& identified,
                                     const CompensationTarget& target, const Eigen::VectorXd& seed) {
  const Eigen::Isometry3d T_shifted = nominal.model().ForwardKinematics(seed) *
                                      identified.model().ForwardKinematics(seed).inverse() * target.T_meas_tool;
  std::vector<IkSolution> starts = ik.AllBranches(T_shifted, seed);
  for (IkSolution& s : ik.AllBranches(target.T_meas_tool, seed)) starts.push_back(std::move(s));
  std::stable_sort(starts.begin(), starts.end(), [&](const IkSolution& a, const IkSolution& b) {
    return (a.q - seed).squaredNorm() < (b.q - seed).squaredNorm();
  });
  return starts;
}

// Throws std::invalid_argument for a target the interface cannot take: non-finite, or joints of another
// count than the arm's.
void CheckTarget(const CompensationTarget& target, int n) {
  if (!target.T_meas_tool.matrix().allFinite()) throw std::invalid_argument("compensate: non-finite target");
  if (target.previous_command.size() != 0 &&
      (target.previous_command.size() != n || !target.previous_command.allFinite())) {
    throw std::invalid_argument("compensate: the previous command has " +
                                std::to_string(target.previous_command.size()) + " joints, expected " +
                                std::to_string(n));
  }
  if (target.seed.size() != 0 && target.seed.size() != n) {
    throw std::invalid_argument("compensate: the seed has " + std::to_string(target.seed.size()) +
                                " joints, expected " + std::to_string(n));
  }
}

}  // namespace

void Compensator::Restart(const CompensationTarget& target, const Eigen::VectorXd& seed,
                          const BranchRestartOptions& options, CompensationResult* result) const {
  const int n = identified_.dof();
  int iterations = result->report.iterations, restarts = 0;
  // A converged trial on the controller's branch ends the search; converged trials elsewhere inside the
  // identified arm's limits are kept, and the one nearest the seed is taken when the branch is not found.
  std::vector<CompensationResult> elsewhere;
  const auto finish = [&](CompensationResult trial, const std::string& message, bool changed) {
    trial.report.seed_computed = result->report.seed_computed;
    trial.report.branch_changed = changed;
    trial.report.message = message;
    trial.report.restarts = restarts;
    trial.report.total_iterations = iterations;
    *result = std::move(trial);
  };
  // Runs the method from `start`; true when it reached the target on the controller's branch.
  const auto attempt = [&](const Eigen::VectorXd& start, const std::string& from) {
    CompensationResult trial;
    trial.q_actual = start;
    DoCompensate(target, start, &trial);
    iterations += trial.report.iterations;
    ++restarts;
    if (trial.report.status != CompensationStatus::kConverged || !trial.q_actual.allFinite() ||
        !WrapIntoLimits(identified_, &seed, trial.q_actual)) {
      return false;
    }
    if (MaxJointDistance(trial.q_actual, seed) <= options.same_branch_distance) {
      finish(std::move(trial), "converged from " + from, false);
      return true;
    }
    trial.report.message = from;
    elsewhere.push_back(std::move(trial));
    return false;
  };

  // 1. The nominal arm's closed-form branches (BranchStarts). Starts on the controller's branch are
  // tried first, the others only when other branches are allowed.
  if (nominal_ik_->has_closed_form() && target.has_orientation) {
    const std::vector<IkSolution> starts = BranchStarts(*nominal_ik_, nominal_, identified_, target, seed);
    for (int pass = 0; pass < (options.other_branches ? 2 : 1) && elsewhere.empty(); ++pass) {
      for (const IkSolution& s : starts) {
        if ((MaxJointDistance(s.q, seed) <= options.same_branch_distance) != (pass == 0)) continue;
        if (attempt(s.q, "the nominal branch " + std::to_string(s.branch) + " of the target")) return;
        if (pass == 1 && !elsewhere.empty()) break;
      }
    }
  }
  // 2. Random starts (a fixed stream), while nothing was found.
  Rng rng(0x6b696e63616cULL);
  const int half = options.random_starts / 2;
  for (int k = 0; k < options.random_starts && elsewhere.empty(); ++k) {
    Eigen::VectorXd start(n);
    const double spread = M_PI * (k + 1) / std::max(half, 1);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = identified_.Limit(j);
      start[j] = k < half ? std::clamp(seed[j] + rng.Uniform(-spread, spread), low, high) : rng.Uniform(low, high);
    }
    if (attempt(start, "a random start")) return;
  }
  if (options.other_branches && !elsewhere.empty()) {
    auto best = std::min_element(elsewhere.begin(), elsewhere.end(), [&](const auto& a, const auto& b) {
      return (a.q_actual - seed).squaredNorm() < (b.q_actual - seed).squaredNorm();
    });
    const std::string from = best->report.message;
    finish(std::move(*best),
           "converged from " + from +
               " on another branch than the controller's: the identified arm does not "
               "reach the target next to the nominal solution (a singular surface or a workspace fold lies between)",
           true);
    return;
  }
  result->report.restarts = restarts;
  result->report.total_iterations = iterations;
}

CompensationResult Compensator::Compensate(const CompensationTarget& target) const {
  if (!prepared_) throw std::logic_error("Compensator::Compensate called before Prepare");
  const auto t0 = std::chrono::steady_clock::now();
  const int n = identified_.dof();
  CheckTarget(target, n);
  CompensationResult result;
  // A seed from a targets file is the controller's joint readings; its joints are the coupled ones.
  Eigen::VectorXd computed_seed;
  const Eigen::VectorXd* seed_in = &target.seed;
  if (target.seed.size() != 0 && nominal_.coupling.size() != 0) {
    computed_seed = nominal_.coupling * target.seed;
    seed_in = &computed_seed;
  }
  if (seed_in->size() == 0) {
    // The controller's solution: closed form where the geometry allows, on the branch closest to where
    // the arm comes from (the previous target), else from the middle of the limits.
    Eigen::VectorXd reference = target.previous_command;
    if (reference.size() != 0 && nominal_.coupling.size() != 0) reference = nominal_.coupling * reference;
    const IkSolution ik = target.has_orientation
                              ? nominal_ik_->Solve(target.T_meas_tool, reference)
                              : nominal_ik_->SolvePosition(target.T_meas_tool.translation(), reference);
    computed_seed = ik.q;
    seed_in = &computed_seed;
    result.report.seed_computed = true;
  }
  const Eigen::VectorXd& seed = *seed_in;
  result.q_actual = seed;
  DoCompensate(target, seed, &result);
  result.report.total_iterations = result.report.iterations;
  // A solution counts only inside the joint limits (revolute joints moved by whole turns towards the seed).
  const auto reached = [&] {
    return result.report.status == CompensationStatus::kConverged && result.q_actual.allFinite() &&
           WrapIntoLimits(identified_, &seed, result.q_actual);
  };
  const BranchRestartOptions* restarts = branch_restarts();
  if (restarts && restarts->enabled && result.q_actual.allFinite() && !reached()) {
    Restart(target, seed, *restarts, &result);
  }
  if (result.q_actual.size() != n || !result.q_actual.allFinite()) {
    result.q_actual = seed;
    result.report.status = CompensationStatus::kFailed;
    result.report.non_finite = true;
    result.report.message = "the method produced no finite solution; the seed is returned";
  }
  const Eigen::Isometry3d T = identified_.model().ForwardKinematics(result.q_actual);
  const Vector6d e = PoseError(T, target.T_meas_tool);
  result.report.position_error = e.head<3>().norm();
  result.report.orientation_error = target.has_orientation ? e.tail<3>().norm() : 0.0;
  // A robot with values out of range (1e300 mm links) gives an infinite error: never "converged".
  if (!std::isfinite(result.report.position_error) || !std::isfinite(result.report.orientation_error)) {
    result.report.status = CompensationStatus::kFailed;
    result.report.message = "the pose error is not finite: values out of range in the robot files";
  } else {
    JudgeErrors(target, &result);
  }
  if (result.report.status == CompensationStatus::kConverged && !reached()) {
    result.report.status = CompensationStatus::kOutOfLimits;
    result.report.message = "reached only outside the identified arm's joint limits";
  }
  // The commands that put the identified arm's joints at q_actual: coupling, ratios and joint errors
  // inverted, the latter coming from the previous target's commands (robot/joint_readings.h).
  double joint_residual = 0.0;
  result.q_command =
      ReadingsFromActual(nominal_, identified_, result.q_actual,
                         target.previous_command.size() ? &target.previous_command : nullptr, &joint_residual);
  if (!result.q_command.allFinite() || joint_residual > 1e-9) {
    result.report.status = CompensationStatus::kFailed;
    result.report.message =
        "the joint errors could not be inverted (residual " + std::to_string(joint_residual) + " rad)";
    if (!result.q_command.allFinite()) result.q_command = result.q_actual;
  }
  if (identified_.drives) result.encoders = nominal_.drives->CommandCounts(result.q_command);
  result.report.wall_time_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace kincal
