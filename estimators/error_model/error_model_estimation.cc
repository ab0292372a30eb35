#include "estimators/error_model/error_model_estimation.h"

#include <algorithm>

#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/selection/select_error_model.h"

namespace kincal {

bool ErrorModelEstimatorOptions::IsValid(std::string* why) const {
  return error_model.IsValid(why) && weighting.IsValid(why) && selection.IsValid(why);
}

void ErrorModelEstimatorOptions::ReadShared(OptionsReader* reader) {
  error_model.Read(reader);
  weighting.Read(reader);
  selection.Read(reader);
}

void EstimateErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                        const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                        const Dataset& data, Robot* identified, EstimationReport* report) {
  if (options.selection.select) {
    SelectErrorModel(estimator, options, budget, minimize, start, controller, data, identified, report);
    return;
  }
  const RowWeighting weighting = options.weighting.Weighting(data.rows.size(), estimator);
  PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options.error_model, weighting);
  if (FinishIfNothingFree(prep, identified, report)) return;
  const double initial_cost = prep.initial.cost;
  Eigen::VectorXd x = prep.problem->InitialX();
  MinimizerRun run = minimize(prep, weighting, budget, &x);
  int iterations = run.iterations;
  if (run.status == EstimationStatus::kConverged && ReanalyzeIdentifiability(x, weighting, &prep, &x)) {
    run = minimize(prep, weighting, std::max(0, budget - iterations), &x);
    iterations += run.iterations;
  }
  report->status = run.status;
  report->message = run.message;
  report->iterations = iterations;
  FinishErrorModel(prep, x, weighting, identified, report);
  nlohmann::json& d = report->details;
  d["prediction_covariance"] = ComputePredictionCovariance(prep, x, weighting).ToJson();
  if (run.details.is_object()) d.update(run.details);
  d["initial_cost_m2"] = initial_cost;
  d["loss"] = options.weighting.loss;
  // The weight of orientation against position in the residuals (m per rad), where rows measured one.
  if (data.HasOrientation()) d["orientation_length_m_per_rad"] = options.error_model.orientation_length;
  if (run.parameters_at_bounds >= 0) ReportParametersAtBounds(estimator, run.parameters_at_bounds, report);
}

void ReportParametersAtBounds(const std::string& solver, int count, EstimationReport* report) {
  report->details["parameters_at_bounds"] = count;
  if (count > 0) {
    report->warnings.push_back(solver + ": " + std::to_string(count) +
                               " parameter(s) ended on a bound: widen the bound_* options if the model allows");
  }
}

}  // namespace kincal
