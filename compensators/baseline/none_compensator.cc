#include "compensators/baseline/none_compensator.h"

namespace kincal {

NoneCompensator::Options NoneCompensator::Options::FromYaml(const YAML::Node& node) {
  OptionsReader reader(node, "none");
  reader.Finish();
  return Options();
}

void NoneCompensator::DoCompensate(const CompensationTarget& /*target*/, const Eigen::VectorXd& seed,
                                   CompensationResult* result) const {
  // Commanding the seed through the nominal ratios turns the real joints by seed * K_nom / K_real.
  result->q_actual = seed;
  if (identified().drives) result->q_actual = DriveModel::ActualFromCommanded(*nominal().drives, *identified().drives, seed);
  result->report.status = CompensationStatus::kConverged;
  result->report.message = "no compensation";
}

}  // namespace kincal
