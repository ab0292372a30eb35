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

// One estimation of the sequence (error_model_estimation.h): the problem it stands in and where it is, the
// iterations it spent, and the best iterate. Each policy is one method; EstimateErrorModel runs them in order.
class Estimation {
 public:
  Estimation(const ErrorModelFitOptions& options, int budget, const ErrorModelMinimizer& minimize,
             RowWeighting weighting, PreparedErrorModel prep)
      : options_(options), budget_(budget), minimize_(minimize), weighting_(std::move(weighting)),
        prep_(std::move(prep)), initial_cost_(prep_.initial.cost), x_(prep_.problem->InitialX()),
        best_{CopyOf(prep_), x_, DataCost(prep_, x_, weighting_)}, start_cost_(best_.cost) {}

  // The first run and, when it converged, the re-analysis of identifiability at its solution.
  void RunAndReanalyze();
  // The weak-parameter hold after a converged run, then the flat-valley rule after a run that used its
  // budget. True when a hold left nothing free (the report is then finished).
  bool HoldWeakAndFlatValley(Robot* identified, EstimationReport* report);
  // Priors weighed by the fit's own noise: restarts until the noise settles.
  void SettlePriorNoise();
  // A fit never ends worse than it started.
  void NeverWorse();
  // Status, message, iterations, the parameters and the details.
  void Report(const std::string& estimator, const Dataset& data, Robot* identified, EstimationReport* report);

 private:
  // One run of the minimiser from x_ with what is left of the budget; the best iterate follows it.
  void RunFrom();
  bool Converged() const { return run_.status == EstimationStatus::kConverged; }
  // Where a bounded solver ended on a bound, the bound decided those parameters, not the data: the weak
  // analysis and the restarts (which re-centre relative parameters such as ratios) are skipped.
  bool FreeOfBounds() const { return run_.parameters_at_bounds <= 0; }
  bool HoldAndRestart(bool own_budget, bool* finished, Robot* identified, EstimationReport* report);

  const ErrorModelFitOptions& options_;
  const int budget_;
  const ErrorModelMinimizer& minimize_;
  const RowWeighting weighting_;
  PreparedErrorModel prep_;
  const double initial_cost_;  // of the first problem at its start, priors included
  Eigen::VectorXd x_;
  int iterations_ = 0;
  int spent_ = 0;  // of the budget, since the last start
  int runs_ = 0;
  MinimizerRun run_;
  BestIterate best_;
  const double start_cost_;
};

void Estimation::RunFrom() {
  run_ = minimize_(prep_, weighting_, std::max(0, budget_ - spent_), &x_);
  if (run_.normal_equations) KeepNormalEquations(x_, weighting_, *run_.normal_equations, &prep_);
  iterations_ += run_.iterations;
  spent_ += run_.iterations;
  ++runs_;
  const double cost = DataCost(prep_, x_, weighting_);
  if (cost < best_.cost) best_ = {CopyOf(prep_), x_, cost, "the end of run " + std::to_string(runs_)};
  // A run that used its budget at a point within 0.1 standard deviations of the minimum reached it.
  if (run_.status == EstimationStatus::kIterationLimit) {
    const NormalEquations ne = NormalEquationsAt(prep_, x_, weighting_);
    if (WithinNoiseOfMinimum(ne, DataSigma(ne, prep_.problem->num_parameters()))) {
      run_.status = EstimationStatus::kConverged;
      run_.message += "; converged all the same: the remaining step is below 0.1 standard deviations";
    }
  }
}

void Estimation::RunAndReanalyze() {
  RunFrom();
  if (Converged() && ReanalyzeIdentifiability(x_, weighting_, &prep_, &x_)) RunFrom();
}

// Holding weak parameters restarts the fit both ways (HoldWeakParameters): the held ones back at their
// start values with the free ones where they are, and the free ones moved with them along the cost's
// valley. Neither is better everywhere: following the valley brings back partners that drifted by degrees
// with a held angle, but where the cost is far from its quadratic model at the solution it can throw them
// into a worse basin. Each restart runs to its end and the one whose final data cost on the training
// rows is lower is kept (a tie keeps the plain reset); the iterations of both count. With `own_budget`
// each restart has a budget of its own; otherwise it has what is left, and one that uses it up starts
// again from its restart with a budget of its own (the valley is followed to first order only). False
// when nothing was held; *finished when every parameter was (the estimation is then finished).
bool Estimation::HoldAndRestart(bool own_budget, bool* finished, Robot* identified, EstimationReport* report) {
  // Both restarts analyse the same solution: its normal equations are computed once.
  KeepNormalEquations(x_, weighting_, NormalEquationsAt(prep_, x_, weighting_), &prep_);
  const PreparedErrorModel before = CopyOf(prep_);
  const Eigen::VectorXd solution = x_;
  const int spent_before = spent_;
  PreparedErrorModel kept_prep;
  Eigen::VectorXd kept_x;
  MinimizerRun kept_run;
  int kept_spent = 0;
  double kept_cost = NAN;
  for (const HoldRestart how : {HoldRestart::kFreeStay, HoldRestart::kFreeFollowValley}) {
    prep_ = CopyOf(before);
    spent_ = own_budget ? 0 : spent_before;
    if (!HoldWeakParameters(solution, weighting_, how, &prep_, &x_)) return false;
    if (FinishIfNothingFree(prep_, identified, report)) return *finished = true;
    const Eigen::VectorXd restart = x_;
    RunFrom();
    if (!own_budget && run_.status == EstimationStatus::kIterationLimit) {
      x_ = restart;
      spent_ = 0;
      RunFrom();
    }
    const double cost = DataCost(prep_, x_, weighting_);
    if (how == HoldRestart::kFreeStay || cost < kept_cost || std::isnan(kept_cost)) {
      kept_prep = CopyOf(prep_);
      kept_x = x_;
      kept_run = run_;
      kept_spent = spent_;
      kept_cost = cost;
    }
  }
  prep_ = std::move(kept_prep);
  x_ = kept_x;
  run_ = kept_run;
  spent_ = kept_spent;
  return true;
}

bool Estimation::HoldWeakAndFlatValley(Robot* identified, EstimationReport* report) {
  bool finished = false;
  if (Converged() && FreeOfBounds() && HoldAndRestart(false, &finished, identified, report) && finished) return true;
  // A run that used its budget in a flat valley is at the bottom in every direction but its weak ones:
  // they are named as at a converged solution, those without a prior held, and the fit starts again from
  // there with a budget of its own (once: a second flat valley keeps its status).
  return run_.status == EstimationStatus::kIterationLimit && FreeOfBounds() &&
         InFlatValley(NormalEquationsAt(prep_, x_, weighting_)) &&
         HoldAndRestart(true, &finished, identified, report) && finished;
}

void Estimation::SettlePriorNoise() {
  if (!(Converged() && FreeOfBounds() && prep_.problem->has_priors() && !(options_.error_model.prior.noise > 0.0)))
    return;
  // Until the noise settles (0.1 %), at most eight restarts.
  for (int pass = 0; pass < 8; ++pass) {
    const double sigma = SigmaAt(prep_, x_, weighting_);
    const double noise = prep_.problem->prior_noise();
    if (!(sigma > 0.0) || std::abs(sigma - noise) <= 1e-3 * noise) break;
    RestartWithPriorNoise(x_, weighting_, sigma, &prep_, &x_);
    RunFrom();
    if (!Converged()) break;
  }
}

// Above its start's data cost (a run that diverged, a hold that left its partners far off), the best
// iterate is returned, and the status says it did not converge.
void Estimation::NeverWorse() {
  const double final_cost = DataCost(prep_, x_, weighting_);
  if (!(final_cost <= start_cost_ * (1.0 + 1e-12))) {  // NaN too
    char costs[160];
    std::snprintf(costs, sizeof(costs), "cost %.6g -> %.6g m^2", start_cost_, final_cost);
    run_.status = EstimationStatus::kFailed;
    run_.message = "the fit ended above its start (" + std::string(costs) + "): returned the best iterate, at " +
                   best_.where + " (" + run_.message + ")";
    prep_ = std::move(best_.prep);
    x_ = best_.x;
  }
}

void Estimation::Report(const std::string& estimator, const Dataset& data, Robot* identified,
                        EstimationReport* report) {
  // Stopped short of the minimum: the parameters weak there are named all the same.
  if (run_.status == EstimationStatus::kIterationLimit && FreeOfBounds()) NameWeakParameters(x_, weighting_, &prep_);
  report->status = run_.status;
  report->message = run_.message;
  report->iterations = iterations_;
  FinishErrorModel(prep_, x_, weighting_, identified, report);
  if (!Converged()) {
    for (const auto& note : prep_.placement_notes) report->warnings.push_back(note);
  }
  nlohmann::json& d = report->details;
  d["prediction_covariance"] = ComputePredictionCovariance(prep_, x_, weighting_).ToJson();
  if (run_.details.is_object()) d.update(run_.details);
  d["initial_cost_m2"] = initial_cost_;
  d["loss"] = options_.weighting.loss;
  // The weight of orientation against position in the residuals (m per rad), where rows measured one.
  if (data.HasOrientation()) d["orientation_length_m_per_rad"] = options_.error_model.orientation_length;
  if (run_.parameters_at_bounds >= 0) ReportParametersAtBounds(estimator, run_.parameters_at_bounds, report);
}

}  // namespace

void EstimateErrorModel(const std::string& estimator, const ErrorModelFitOptions& options, int budget,
                        const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                        const Dataset& data, Robot* identified, EstimationReport* report) {
  RowWeighting weighting = options.weighting.Weighting(data.rows.size(), estimator);
  PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options.error_model, weighting);
  if (FinishIfNothingFree(prep, identified, report)) return;
  Estimation e(options, budget, minimize, std::move(weighting), std::move(prep));
  e.RunAndReanalyze();
  if (e.HoldWeakAndFlatValley(identified, report)) return;
  e.SettlePriorNoise();
  e.NeverWorse();
  e.Report(estimator, data, identified, report);
}

void ReportParametersAtBounds(const std::string& solver, int count, EstimationReport* report) {
  report->details["parameters_at_bounds"] = count;
  if (count > 0) {
    report->warnings.push_back(solver + ": " + std::to_string(count) +
                               " parameter(s) ended on a bound: widen the bound_* options if the model allows");
  }
}

}  // namespace kincal
