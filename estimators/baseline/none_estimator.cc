#include "estimators/baseline/none_estimator.h"

namespace kincal {

const OptionTable<NoneEstimator::Options>& NoneEstimator::Options::Table() {
  static const OptionTable<Options> table("none");
  return table;
}

void NoneEstimator::DoEstimate(const Robot& start, const Robot& /*controller*/, const Dataset& /*data*/,
                               Robot* identified, EstimationReport* report) const {
  *identified = start;
  report->status = EstimationStatus::kConverged;
  report->message = "no calibration: the input robot is returned unchanged";
}

}  // namespace kincal
