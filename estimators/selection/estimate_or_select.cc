#include "estimators/selection/estimate_or_select.h"

#include "estimators/selection/select_error_model.h"

namespace kincal {

const OptionTable<ErrorModelEstimatorOptions>& ErrorModelEstimatorOptions::Table() {
  using O = ErrorModelEstimatorOptions;
  static const OptionTable<O> table = OptionTable<O>("error model estimator")
                                          .Include(ErrorModelFitOptions::Table())
                                          .Include(ModelSelectionOptions::Table(), &O::selection);
  return table;
}

bool ErrorModelEstimatorOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

void EstimateOrSelectErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                                const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                                const Dataset& data, Robot* identified, EstimationReport* report) {
  if (options.selection.select) {
    SelectErrorModel(estimator, options, budget, minimize, start, controller, data, identified, report);
    return;
  }
  EstimateErrorModel(estimator, options, budget, minimize, start, controller, data, identified, report);
  if (options.selection.cross_validate) {
    CrossValidateErrorModel(estimator, options, budget, minimize, start, controller, data, report);
  }
}

}  // namespace kincal
