#include "estimators/nlopt/nlopt_estimator.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include <nlopt.hpp>

#include "estimators/bounded/scaled_error_model.h"

namespace kincal {
namespace {

// Local algorithms that honour bound constraints (NLopt's documentation, "NLopt Algorithms").
const std::vector<std::string>& SupportedAlgorithms() {
  static const std::vector<std::string> names = {
      "LD_SLSQP",  "LD_LBFGS",  "LD_MMA",          "LD_CCSAQ",
      "LD_VAR1",   "LD_VAR2",   "LD_TNEWTON",      "LD_TNEWTON_PRECOND_RESTART",
      "LN_BOBYQA", "LN_COBYLA", "LN_NEWUOA_BOUND", "LN_NELDERMEAD",
      "LN_SBPLX"};
  return names;
}

// NLopt's objective: the scaled cost and, when NLopt asks for it, its gradient (scaled_error_model.h).
class Objective {
 public:
  explicit Objective(const ScaledErrorModel& model) : model_(model) {}
  static double Call(const std::vector<double>& y, std::vector<double>& gradient, void* self) {
    return static_cast<Objective*>(self)->Evaluate(y, gradient);
  }
  int evaluations() const { return evaluations_; }

 private:
  double Evaluate(const std::vector<double>& y, std::vector<double>& gradient) {
    ++evaluations_;
    const bool with_gradient = !gradient.empty();
    const NormalEquations ne = model_.Evaluate(y.data(), with_gradient ? Accumulate::kGradient : Accumulate::kCost);
    if (!std::isfinite(ne.cost)) return HUGE_VAL;
    if (with_gradient) Eigen::Map<Eigen::VectorXd>(gradient.data(), model_.size()) = model_.Gradient(ne);
    return model_.Cost(ne);
  }
  const ScaledErrorModel& model_;
  int evaluations_ = 0;
};

std::string ResultName(nlopt::result r) {
  switch (r) {
    case nlopt::FAILURE:
      return "generic failure";
    case nlopt::INVALID_ARGS:
      return "invalid arguments";
    case nlopt::OUT_OF_MEMORY:
      return "out of memory";
    case nlopt::ROUNDOFF_LIMITED:
      return "roundoff limited";
    case nlopt::FORCED_STOP:
      return "forced stop";
    case nlopt::SUCCESS:
      return "success";
    case nlopt::STOPVAL_REACHED:
      return "stopval reached";
    case nlopt::FTOL_REACHED:
      return "function tolerance reached";
    case nlopt::XTOL_REACHED:
      return "parameter tolerance reached";
    case nlopt::MAXEVAL_REACHED:
      return "evaluation limit reached";
    case nlopt::MAXTIME_REACHED:
      return "time limit reached";
    default:
      return "result " + std::to_string(static_cast<int>(r));
  }
}

// Minimises from the prepared problem's start within the bounds (`bounds` by name, see
// scaled_error_model.h) with at most max_evaluations passes; *x ends at the best point NLopt found.
MinimizerRun Minimize(const PreparedErrorModel& prep, const RowWeighting& weighting, const NamedBounds& bounds,
                      const NloptOptions& options, int max_evaluations, Eigen::VectorXd* x) {
  MinimizerRun run;
  const ScaledErrorModel model(*prep.problem, prep.initial, bounds, weighting);
  const int p = model.size();
  Objective objective(model);
  nlopt::opt opt(options.algorithm.c_str(), static_cast<unsigned>(p));
  opt.set_lower_bounds(std::vector<double>(model.y_lower().data(), model.y_lower().data() + p));
  opt.set_upper_bounds(std::vector<double>(model.y_upper().data(), model.y_upper().data() + p));
  opt.set_min_objective(&Objective::Call, &objective);
  opt.set_ftol_rel(options.function_tolerance);
  opt.set_xtol_abs(options.parameter_tolerance);
  opt.set_maxeval(std::max(1, max_evaluations));
  if (options.max_time_seconds > 0.0) opt.set_maxtime(options.max_time_seconds);
  std::vector<double> y(p, 0.0);
  double f = 0.0;
  try {
    opt.optimize(y, f);
  } catch (const std::exception&) {
    // NLopt throws for its negative results; the code says which, and y holds the best point.
  }
  const nlopt::result result = opt.last_optimize_result();
  run.iterations = objective.evaluations();  // NLopt counts evaluations, not iterations
  run.parameters_at_bounds = model.CountAtBounds(y.data());
  *x = model.X(y.data());
  switch (result) {
    case nlopt::SUCCESS:
    case nlopt::STOPVAL_REACHED:
    case nlopt::FTOL_REACHED:
    case nlopt::XTOL_REACHED:
      run.status = EstimationStatus::kConverged;
      break;
    case nlopt::MAXEVAL_REACHED:
    case nlopt::MAXTIME_REACHED:
      run.status = EstimationStatus::kIterationLimit;
      break;
    default:
      run.status = EstimationStatus::kFailed;
      break;
  }
  run.message = options.algorithm + ": " + ResultName(result);
  run.details = {{"algorithm", options.algorithm}, {"nlopt_result", static_cast<int>(result)}};
  return run;
}

}  // namespace

const OptionTable<NloptOptions>& NloptOptions::Table() {
  using O = NloptOptions;
  static const OptionTable<O> table =
      OptionTable<O>("nlopt")
          .Include(ErrorModelEstimatorOptions::Table())
          .Add("algorithm", &O::algorithm, "a bounded NLopt local algorithm (LD_SLSQP, LN_BOBYQA, ...)",
               OneOf(SupportedAlgorithms()))
          .Add("max_evaluations", &O::max_evaluations, "cost (and gradient) evaluations", AtLeast(1))
          .Add("max_time_seconds", &O::max_time_seconds, "wall time limit, s; 0: none", NonNegative())
          .Add("function_tolerance", &O::function_tolerance, "NLopt ftol_rel", NonNegative())
          .Add("parameter_tolerance", &O::parameter_tolerance, "NLopt xtol_abs on the scaled variables", NonNegative());
  return table;
}

bool NloptOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

NloptOptions NloptOptions::FromYaml(const YAML::Node& node) { return Table().Read(node); }

void NloptEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                EstimationReport* report) const {
  // Bounds of the first problem, kept by name when identifiability is re-analysed (scaled_error_model.h).
  std::optional<NamedBounds> bounds;
  int evaluations = 0;
  const auto minimize = [&](const PreparedErrorModel& prep, const RowWeighting& weighting, int budget,
                            Eigen::VectorXd* x) {
    if (!bounds) bounds = BoundsByName(*prep.problem);
    MinimizerRun run = Minimize(prep, weighting, *bounds, options_, budget, x);
    evaluations += run.iterations;
    run.details["evaluations"] = evaluations;
    return run;
  };
  EstimateOrSelectErrorModel(name(), options_, options_.max_evaluations, minimize, start, controller, data, identified, report);
}

}  // namespace kincal
