#pragma once
// The entry the four error-model estimators (least_squares, ceres, nlopt, ipopt) call: selection and
// cross-validation as a layer above the fit (estimators/error_model/error_model_estimation.h), which knows
// nothing of them.
//
// Options (ErrorModelEstimatorOptions, read once for all four): the fit's keys (ErrorModelFitOptions: the
// error model's and the row weighting's) and the selection's (select, select_folds, cross_validate;
// model_selection.h). Each estimator's options derive from them and its table includes theirs first.
//
// With `select: true`, SelectErrorModel (select_error_model.h) scores the nested candidates by blocked
// cross-validation and fits the chosen one; otherwise EstimateErrorModel fits the file's model and, with
// `cross_validate: true`, CrossValidateErrorModel adds the model-inadequacy tau of its predicted sd.
#include <string>

#include "estimators/error_model/error_model_estimation.h"
#include "estimators/selection/model_selection.h"

namespace kincal {

struct ErrorModelEstimatorOptions : ErrorModelFitOptions {
  ModelSelectionOptions selection;  // keys select, select_folds, cross_validate (model_selection.h)

  // ErrorModelFitOptions' keys, then the selection's; each estimator's table includes this one first.
  static const OptionTable<ErrorModelEstimatorOptions>& Table();
  bool IsValid(std::string* why) const;
};

// Selects (select: true) or fits (EstimateErrorModel), then cross-validates (cross_validate: true without
// select). Arguments as EstimateErrorModel's. Throws std::invalid_argument for bad input.
void EstimateOrSelectErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                                const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                                const Dataset& data, Robot* identified, EstimationReport* report);

}  // namespace kincal
