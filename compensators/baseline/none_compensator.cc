#include "compensators/baseline/none_compensator.h"

#include <Eigen/LU>

#include "robot/joint_readings.h"

namespace kincal {

const OptionTable<NoneCompensator::Options>& NoneCompensator::Options::Table() {
  static const OptionTable<Options> table("none");
  return table;
}

void NoneCompensator::DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                                   CompensationResult* result) const {
  // The controller commands its own solution: the real joints go where those readings put them
  // (coupling, ratios and joint errors of the identified arm, robot/joint_readings.h).
  Eigen::VectorXd readings = target.seed;
  if (readings.size() == 0) {
    readings = nominal().coupling.size() ? Eigen::VectorXd(nominal().coupling.partialPivLu().solve(seed)) : seed;
  }
  result->q_actual = ActualFromReadings(nominal(), identified(), readings,
                                        target.previous_command.size() ? &target.previous_command : nullptr);
  result->report.status = CompensationStatus::kConverged;
  result->report.message = "no compensation";
}

}  // namespace kincal
