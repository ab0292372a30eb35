#include "estimators/baseline/none_estimator.h"

#include "robot/fixture_fits.h"

namespace kincal {

const OptionTable<NoneEstimator::Options>& NoneEstimator::Options::Table() {
  static const OptionTable<Options> table("none");
  return table;
}

void NoneEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data,
                               Robot* identified, EstimationReport* report) const {
  *identified = start;
  // Fixtures the data name but the robot does not give (pivots, planes, sockets) are placed where a fit
  // would start them, so that the uncalibrated arm is scored on every instrument.
  if (!data.AllFullPoints()) identified->fixtures = StartFixtures(controller, start, data);
  report->status = EstimationStatus::kConverged;
  report->message = "no calibration: the input robot is returned unchanged";
}

}  // namespace kincal
