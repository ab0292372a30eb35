#pragma once
// The identified parameters of one work item in report units, with what the estimators said of each: the
// standard deviation and, from error-model fits with priors (estimators/error_model/error_model.h,
// PriorOptions), the prior's sd, the sd the data alone give, the data's share of the information and the
// weak-identifiability flag with the parameters it trades against.
#include <cmath>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "robot/robot.h"

namespace kincal {

// An identified parameter in report units: mm, deg, or dimensionless for ratios; joint-error coefficients
// in deg, deg/mm or s.
struct ParameterRow {
  std::string name;
  std::string unit;
  double nominal = NAN, estimate = NAN, stddev = NAN, truth = NAN;
  // From the last estimator of the pipeline that estimated the parameter (NaN / false / "" otherwise).
  double prior_sd = NAN;       // the prior's sd, NaN without a prior
  double data_sd = NAN;        // the sd the data alone give (stddev is the posterior's with a prior)
  double data_share = NAN;     // 1 - stddev^2 / prior_sd^2: the share of the information from the data
  bool weak = false;           // weakly identifiable (data_sd above the prior's or its kind's reference sd)
  std::string trades_against;  // a weak parameter's partners, space-separated
};

// Every parameter of `identified` (geometry, markers, joint-error coefficients, ratios), with the nominal's
// and the truth's values (`truth` may be null) and what the last of `reports` estimating it reported.
std::vector<ParameterRow> ParameterRows(const Robot& nominal, const Robot* truth, const Robot& identified,
                                        const std::vector<EstimationReport>& reports);

}  // namespace kincal
