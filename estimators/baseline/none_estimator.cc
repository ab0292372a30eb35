#include "estimators/baseline/none_estimator.h"

namespace kincal {

NoneEstimator::Options NoneEstimator::Options::FromYaml(const YAML::Node& node) {
  OptionsReader reader(node, "none");
  reader.Finish();
  return Options();
}

void NoneEstimator::DoEstimate(const Robot& start, const Robot& /*controller*/, const Dataset& /*data*/,
                               Robot* identified, EstimationReport* report) const {
  *identified = start;
  report->status = EstimationStatus::kConverged;
  report->message = "no calibration: the input robot is returned unchanged";
}

}  // namespace kincal
