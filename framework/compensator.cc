#include "framework/compensator.h"

#include <chrono>
#include <algorithm>
#include <cmath>

#include "framework/nominal_ik.h"
#include "framework/joint_readings.h"
#include "framework/math.h"

namespace kincal {

std::string ToString(CompensationStatus status) {
  switch (status) {
    case CompensationStatus::kConverged: return "converged";
    case CompensationStatus::kIterationLimit: return "iteration_limit";
    case CompensationStatus::kSingular: return "singular";
    case CompensationStatus::kUnreachable: return "unreachable";
    case CompensationStatus::kFailed: return "failed";
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
  nominal_ = nominal;
  identified_ = identified;
  nominal_ik_ = std::make_shared<const NominalInverseKinematics>(nominal_);
  prepared_ = true;
  DoPrepare();
}

void Compensator::RestartFromBranches(const CompensationTarget& target, const Eigen::VectorXd& seed,
                                      CompensationResult* result) const {
  // Next to a singular configuration the identified arm's solution can lie on the other side of it, out
  // of reach of an iteration from the seed (the branches of the nominal arm meet there, the identified
  // arm's do not at the same place). The nominal arm's closed-form branches for the target moved by the
  // pose error at the seed, T_nominal(seed) T_identified(seed)^-1 T_target (the pose whose nominal
  // solution the identified arm puts at the target, to first order), are starts on every side; the
  // nearest to the seed first.
  const Eigen::Isometry3d T_shifted = nominal_.model().ForwardKinematics(seed) *
                                      identified_.model().ForwardKinematics(seed).inverse() * target.T_meas_tool;
  std::vector<IkSolution> starts = nominal_ik_->AllBranches(T_shifted, seed);
  std::sort(starts.begin(), starts.end(), [&](const IkSolution& a, const IkSolution& b) {
    return (a.q - seed).squaredNorm() < (b.q - seed).squaredNorm();
  });
  int iterations = result->report.iterations;
  // Only the controller's branch counts: a solution farther than this from the seed in any joint is
  // another configuration (the arm would turn over), not a compensation of this one.
  constexpr double kSameBranch = 0.5;  // rad
  for (const IkSolution& start : starts) {
    if ((start.q - seed).cwiseAbs().maxCoeff() > kSameBranch) continue;
    CompensationResult trial;
    trial.q_actual = start.q;
    DoCompensate(target, start.q, &trial);
    iterations += trial.report.iterations;
    if (trial.report.status == CompensationStatus::kConverged && trial.q_actual.allFinite() &&
        (trial.q_actual - seed).cwiseAbs().maxCoeff() <= kSameBranch) {
      trial.report.seed_computed = result->report.seed_computed;
      trial.report.message = "converged from the nominal branch " + std::to_string(start.branch) +
                             " of the target corrected by the pose error at the seed";
      *result = std::move(trial);
      break;
    }
  }
  result->report.iterations = iterations;
}

CompensationResult Compensator::Compensate(const CompensationTarget& target) const {
  if (!prepared_) throw std::logic_error("Compensator::Compensate called before Prepare");
  const auto t0 = std::chrono::steady_clock::now();
  const int n = identified_.dof();
  if (!target.T_meas_tool.matrix().allFinite()) throw std::invalid_argument("compensate: non-finite target");
  if (target.previous_command.size() != 0 && (target.previous_command.size() != n || !target.previous_command.allFinite())) {
    throw std::invalid_argument("compensate: the previous command has " + std::to_string(target.previous_command.size()) +
                                " joints, expected " + std::to_string(n));
  }
  if (target.seed.size() != 0 && target.seed.size() != n) {
    throw std::invalid_argument("compensate: the seed has " + std::to_string(target.seed.size()) + " joints, expected " +
                                std::to_string(n));
  }
  CompensationResult result;
  // A seed from a targets file is the controller's joint readings; its joints are the coupled ones.
  Eigen::VectorXd seed = target.seed;
  if (seed.size() != 0 && nominal_.coupling.size() != 0) seed = nominal_.coupling * seed;
  if (seed.size() == 0) {
    // The controller's solution: closed form where the geometry allows, on the branch closest to where
    // the arm comes from (the previous target), else from the middle of the limits.
    Eigen::VectorXd reference = target.previous_command;
    if (reference.size() != 0 && nominal_.coupling.size() != 0) reference = nominal_.coupling * reference;
    const IkSolution ik = target.has_orientation ? nominal_ik_->Solve(target.T_meas_tool, reference)
                                                 : nominal_ik_->SolvePosition(target.T_meas_tool.translation(), reference);
    seed = ik.q;
    result.report.seed_computed = true;
  }
  result.q_actual = seed;
  DoCompensate(target, seed, &result);
  if (result.report.status != CompensationStatus::kConverged && RestartsFromBranches() && target.has_orientation &&
      nominal_ik_->has_closed_form() && result.q_actual.allFinite()) {
    RestartFromBranches(target, seed, &result);
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
  }
  // The commands that put the identified arm's joints at q_actual: coupling, ratios and joint errors
  // inverted, the latter coming from the previous target's commands (framework/joint_readings.h).
  double joint_residual = 0.0;
  result.q_command = ReadingsFromActual(nominal_, identified_, result.q_actual,
                                        target.previous_command.size() ? &target.previous_command : nullptr,
                                        &joint_residual);
  if (!result.q_command.allFinite() || joint_residual > 1e-9) {
    result.report.status = CompensationStatus::kFailed;
    result.report.message = "the joint errors could not be inverted (residual " + std::to_string(joint_residual) + " rad)";
    if (!result.q_command.allFinite()) result.q_command = result.q_actual;
  }
  if (identified_.drives) result.encoders = nominal_.drives->CommandCounts(result.q_command);
  result.report.wall_time_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace kincal
