#pragma once
// What the four error-model estimators (least_squares, ceres, nlopt, ipopt) share beyond the problem:
// one set of option keys and one estimation sequence, so that they differ only in how they minimise.
//
// Options (ErrorModelFitOptions): the error model's keys (fixed, identify_*, initialize_bases,
// orientation_length, identifiability_tolerance, prior and the bound_* keys, used by the bounded solvers)
// and the row weighting (loss, loss_scale, weights): every estimator minimises sum_i w_i rho(|r_i|^2)
// (normal_equations.h). The estimators call this fit through the selection layer above it
// (estimators/selection/estimate_or_select.h), whose options add the selection's keys to these.
//
// Sequence (EstimateErrorModel; the selection runs it per candidate and fold):
//   1. PrepareErrorModel: place bases, tool and markers in closed form, hold what the data cannot
//      determine (error_model.h); nothing free: converged after zero iterations.
//   2. the backend's Minimizer from problem->InitialX() with the whole iteration budget;
//   3. converged: ReanalyzeIdentifiability at the solution and, when it frees or holds parameters, the
//      Minimizer again from there with what is left of the budget;
//   3b. converged: HoldWeakParameters (weak_parameters.h) names the weak parameters and holds those
//      without a prior, and the Minimizer runs again from two restarts (the free parameters where they
//      are, and moved along the cost's valley), the one with the lower training data cost kept; a run
//      that ended at the iteration limit in a flat valley (InFlatValley, error_model.h) gets the same
//      analysis, then a budget of its own;
//   3c. converged, with priors and no given prior noise: the priors weighed by the fit's own noise,
//      restarting (RestartWithPriorNoise, under the re-analysis's rule) until the noise settles;
//   4. never worse: a sequence whose data cost ended above its start returns its best iterate, `failed`;
//   5. status, message and iterations (summed) from the runs; FinishErrorModel; details initial_cost_m2
//      and loss; bounded solvers: parameters_at_bounds and a warning when any (ReportParametersAtBounds).
// Each policy is one step of the estimation in error_model_estimation.cc.
// Each backend maps its own return codes to a MinimizerRun (converged, iteration limit, failed).
#include <functional>
#include <memory>
#include <string>

#include "estimators/error_model/error_model.h"
#include "estimators/error_model/row_weighting_options.h"
#include "estimators/estimator.h"

namespace kincal {

struct ErrorModelFitOptions {
  ErrorModelOptions error_model;  // error_model_problem.h
  RowWeightingOptions weighting;  // robust loss and per-row weights (keys loss, loss_scale, weights)

  // The keys of the two tables above.
  static const OptionTable<ErrorModelFitOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct MinimizerRun {
  EstimationStatus status = EstimationStatus::kFailed;
  std::string message;
  int iterations = 0;             // in the unit the budget counts (iterations or evaluations)
  int parameters_at_bounds = -1;  // bounded solvers: how many ended on a bound; -1 for unbounded ones
  nlohmann::json details;         // backend details of this run (the last run's are reported)
  // AccumulateNormalEquations(*prep.problem, *x, weighting) where the run ended, when the backend has
  // them from a pass at that very x (null otherwise): the analyses there read them.
  std::shared_ptr<const NormalEquations> normal_equations;
};

// Minimises prep's problem from *x (its InitialX()) with `weighting` in at most `budget` iterations;
// *x ends at the point the backend returns.
using ErrorModelMinimizer = std::function<MinimizerRun(const PreparedErrorModel& prep, const RowWeighting& weighting,
                                                       int budget, Eigen::VectorXd* x)>;

// Steps 1-4 above. `estimator` names the estimator in messages. Throws std::invalid_argument for bad
// input (PrepareErrorModel's conditions, weights not one per row).
void EstimateErrorModel(const std::string& estimator, const ErrorModelFitOptions& options, int budget,
                        const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                        const Dataset& data, Robot* identified, EstimationReport* report);

// Records how many parameters a bounded solver left on a bound (details.parameters_at_bounds) and, if any,
// warns that the bounds, not the data, decided them.
void ReportParametersAtBounds(const std::string& solver, int count, EstimationReport* report);

}  // namespace kincal
