#include "estimators/error_model/error_model_estimation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "estimators/error_model/prediction_uncertainty.h"

namespace kincal {

const OptionTable<ErrorModelFitOptions>& ErrorModelFitOptions::Table() {
  using O = ErrorModelFitOptions;
  static const OptionTable<O> table = OptionTable<O>("error model fit")
                                          .Include(ErrorModelOptions::Table(), &O::error_model)
                                          .Include(RowWeightingOptions::Table(), &O::weighting);
  return table;
}

bool ErrorModelFitOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

namespace {

// The fit's own noise per residual at x, the data alone.
double SigmaAt(const PreparedErrorModel& prep, const Eigen::VectorXd& x, const RowWeighting& weighting) {
  return DataSigma(NormalEquationsAt(prep, x, weighting, Accumulate::kCost, false), prep.problem->num_parameters());
}

// The data's own cost at x (no prior terms): a fit from its start may never end above it. With priors the
// start sits at the prior means, so the posterior's minimum has a data cost no higher than the start's.
double DataCost(const PreparedErrorModel& prep, const Eigen::VectorXd& x, const RowWeighting& weighting) {
  return NormalEquationsAt(prep, x, weighting, Accumulate::kCost, false).cost;
}

PreparedErrorModel CopyOf(const PreparedErrorModel& p) {
  PreparedErrorModel c;
  c.input = p.input;
  c.start = p.start;
  c.placed = p.placed;
  c.problem = std::make_unique<ErrorModelProblem>(*p.problem);  // the rows stay shared
  c.identifiability = p.identifiability;
  c.initial = p.initial;
  c.registered_rms = p.registered_rms;
  c.warnings = p.warnings;
  c.placement_notes = p.placement_notes;
  c.weak = p.weak;
  c.weak_held = p.weak_held;
  c.evaluated = p.evaluated;
  return c;
}

// The lowest data cost the estimation has stood at (its start, or where a run ended), with the problem it
// stood in: what is returned when the sequence ends above its start.
struct BestIterate {
  PreparedErrorModel prep;
  Eigen::VectorXd x;
  double cost = 0.0;
  std::string where = "its start";
};

}  // namespace

void EstimateErrorModel(const std::string& estimator, const ErrorModelFitOptions& options, int budget,
                        const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                        const Dataset& data, Robot* identified, EstimationReport* report) {
  const RowWeighting weighting = options.weighting.Weighting(data.rows.size(), estimator);
  PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options.error_model, weighting);
  if (FinishIfNothingFree(prep, identified, report)) return;
  const double initial_cost = prep.initial.cost;
  Eigen::VectorXd x = prep.problem->InitialX();
  int iterations = 0;
  int spent = 0;  // of the budget, since the last start
  // A run that used its budget at a point within 0.1 standard deviations of the minimum reached it.
  BestIterate best{CopyOf(prep), x, DataCost(prep, x, weighting)};
  const double start_cost = best.cost;
  int runs = 0;
  const auto run_from = [&]() {
    MinimizerRun run = minimize(prep, weighting, std::max(0, budget - spent), &x);
    if (run.normal_equations) KeepNormalEquations(x, weighting, *run.normal_equations, &prep);
    iterations += run.iterations;
    spent += run.iterations;
    ++runs;
    const double cost = DataCost(prep, x, weighting);
    if (cost < best.cost) best = {CopyOf(prep), x, cost, "the end of run " + std::to_string(runs)};
    if (run.status == EstimationStatus::kIterationLimit) {
      const NormalEquations ne = NormalEquationsAt(prep, x, weighting);
      if (WithinNoiseOfMinimum(ne, DataSigma(ne, prep.problem->num_parameters()))) {
        run.status = EstimationStatus::kConverged;
        run.message += "; converged all the same: the remaining step is below 0.1 standard deviations";
      }
    }
    return run;
  };
  const auto converged = [](const MinimizerRun& run) { return run.status == EstimationStatus::kConverged; };
  MinimizerRun run = run_from();
  if (converged(run) && ReanalyzeIdentifiability(x, weighting, &prep, &x)) run = run_from();
  // Where a bounded solver ended on a bound, the bound decided those parameters, not the data: the weak
  // analysis and the restarts below (which re-centre relative parameters such as ratios) are skipped.
  const auto free_of_bounds = [](const MinimizerRun& r) { return r.parameters_at_bounds <= 0; };
  // Holding weak parameters restarts the fit both ways (HoldWeakParameters): the held ones back at their
  // start values with the free ones where they are, and the free ones moved with them along the cost's
  // valley. Neither is better everywhere: following the valley brings back partners that drifted by degrees
  // with a held angle, but where the cost is far from its quadratic model at the solution it can throw them
  // into a worse basin. Each restart runs to its end and the one whose final data cost on the training
  // rows is lower is kept (a tie keeps the plain reset); the iterations of both count. With `own_budget`
  // each restart has a budget of its own; otherwise it has what is left, and one that uses it up starts
  // again from its restart with a budget of its own (the valley is followed to first order only). False
  // when nothing was held; *finished when every parameter was (the estimation is then finished).
  const auto hold_and_restart = [&](bool own_budget, bool* finished) {
    // Both restarts analyse the same solution: its normal equations are computed once.
    KeepNormalEquations(x, weighting, NormalEquationsAt(prep, x, weighting), &prep);
    const PreparedErrorModel before = CopyOf(prep);
    const Eigen::VectorXd solution = x;
    const int spent_before = spent;
    PreparedErrorModel kept_prep;
    Eigen::VectorXd kept_x;
    MinimizerRun kept_run;
    int kept_spent = 0;
    double kept_cost = NAN;
    for (const HoldRestart how : {HoldRestart::kFreeStay, HoldRestart::kFreeFollowValley}) {
      prep = CopyOf(before);
      spent = own_budget ? 0 : spent_before;
      if (!HoldWeakParameters(solution, weighting, how, &prep, &x)) return false;
      if (FinishIfNothingFree(prep, identified, report)) return *finished = true;
      const Eigen::VectorXd restart = x;
      run = run_from();
      if (!own_budget && run.status == EstimationStatus::kIterationLimit) {
        x = restart;
        spent = 0;
        run = run_from();
      }
      const double cost = DataCost(prep, x, weighting);
      if (how == HoldRestart::kFreeStay || cost < kept_cost || std::isnan(kept_cost)) {
        kept_prep = CopyOf(prep);
        kept_x = x;
        kept_run = run;
        kept_spent = spent;
        kept_cost = cost;
      }
    }
    prep = std::move(kept_prep);
    x = kept_x;
    run = kept_run;
    spent = kept_spent;
    return true;
  };
  bool finished = false;
  if (converged(run) && free_of_bounds(run) && hold_and_restart(false, &finished) && finished) return;
  // A run that used its budget in a flat valley is at the bottom in every direction but its weak ones:
  // they are named as at a converged solution, those without a prior held, and the fit starts again from
  // there with a budget of its own (once: a second flat valley keeps its status).
  if (run.status == EstimationStatus::kIterationLimit && free_of_bounds(run) &&
      InFlatValley(NormalEquationsAt(prep, x, weighting)) && hold_and_restart(true, &finished) &&
      finished) {
    return;
  }
  // Priors weighed by the fit's own noise: repeat until the noise settles (0.1 %).
  if (converged(run) && free_of_bounds(run) && prep.problem->has_priors() && !(options.error_model.prior.noise > 0.0)) {
    for (int pass = 0; pass < 8; ++pass) {
      const double sigma = SigmaAt(prep, x, weighting);
      const double noise = prep.problem->prior_noise();
      if (!(sigma > 0.0) || std::abs(sigma - noise) <= 1e-3 * noise) break;
      RestartWithPriorNoise(x, weighting, sigma, &prep, &x);
      run = run_from();
      if (!converged(run)) break;
    }
  }
  // A fit never ends worse than it started: above its start's data cost (a run that diverged, a hold that
  // left its partners far off), the best iterate is returned, and the status says it did not converge.
  const double final_cost = DataCost(prep, x, weighting);
  if (!(final_cost <= start_cost * (1.0 + 1e-12))) {  // NaN too
    char costs[160];
    std::snprintf(costs, sizeof(costs), "cost %.6g -> %.6g m^2", start_cost, final_cost);
    run.status = EstimationStatus::kFailed;
    run.message = "the fit ended above its start (" + std::string(costs) + "): returned the best iterate, at " +
                  best.where + " (" + run.message + ")";
    prep = std::move(best.prep);
    x = best.x;
  }
  // Stopped short of the minimum: the parameters weak there are named all the same.
  if (run.status == EstimationStatus::kIterationLimit && free_of_bounds(run)) NameWeakParameters(x, weighting, &prep);
  report->status = run.status;
  report->message = run.message;
  report->iterations = iterations;
  FinishErrorModel(prep, x, weighting, identified, report);
  if (!converged(run)) {
    for (const auto& note : prep.placement_notes) report->warnings.push_back(note);
  }
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
