#include "framework/compensator.h"

#include <chrono>
#include <cmath>

#include "framework/inverse_kinematics.h"
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
  prepared_ = true;
  DoPrepare();
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
    const InverseKinematicsResult ik =
        SolveInverseKinematics(nominal_, target.T_meas_tool, target.has_orientation, Eigen::VectorXd(), {});
    seed = ik.q;
    result.report.seed_computed = true;
  }
  result.q_actual = seed;
  DoCompensate(target, seed, &result);
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
