#pragma once
// The error-model estimators' `select: true` (model_selection.h for the candidates, the folds, the score
// and the rule): scores every nested candidate by blocked K-fold cross-validation on `data` (the training
// rows), then fits the chosen one on all of them with the estimator's own minimiser. The report is the
// final fit's, with details.selection (the table) and the candidate's name in the message.
#include <string>

#include "estimators/selection/estimate_or_select.h"

namespace kincal {

void SelectErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                      const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                      const Dataset& data, Robot* identified, EstimationReport* report);

// `cross_validate: true` without `select`: the same blocked folds for `start` itself (each fold fits it on
// the other blocks), for its model-inadequacy tau (prediction_uncertainty.h (3)); writes tau into
// report->details.prediction_covariance and the CV table (one row) into details.cross_validation.
void CrossValidateErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                             const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                             const Dataset& data, EstimationReport* report);

}  // namespace kincal
