#include "estimators/ipopt/ipopt_estimator.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpSolveStatistics.hpp>

#include "estimators/ipopt/error_model_nlp.h"

namespace kincal {
namespace {

std::string ReturnName(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded:
      return "solved";
    case Ipopt::Solved_To_Acceptable_Level:
      return "solved to the acceptable level";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "search direction became too small";
    case Ipopt::Diverging_Iterates:
      return "diverging iterates";
    case Ipopt::User_Requested_Stop:
      return "stopped by the user";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "iteration limit reached";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "time limit reached";
    case Ipopt::Restoration_Failed:
      return "restoration failed";
    case Ipopt::Error_In_Step_Computation:
      return "error in step computation";
    case Ipopt::Invalid_Number_Detected:
      return "invalid number detected (non-finite cost)";
    default:
      return "return status " + std::to_string(static_cast<int>(s));
  }
}

EstimationStatus StatusOf(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level:
      return EstimationStatus::kConverged;
    case Ipopt::Maximum_Iterations_Exceeded:
    case Ipopt::Maximum_CpuTime_Exceeded:
      return EstimationStatus::kIterationLimit;
    default:
      return EstimationStatus::kFailed;
  }
}

// Minimises from the prepared problem's start within the bounds (`bounds` by name, see
// scaled_error_model.h); *x ends at Ipopt's final point.
MinimizerRun Minimize(const PreparedErrorModel& prep, const RowWeighting& weighting, const NamedBounds& bounds,
                      const IpoptOptions& options, int max_iterations, Eigen::VectorXd* x, int* passes) {
  // Debian's Ipopt 3.11 solves its linear systems with sequential MUMPS, whose state is global: two solves
  // at once (a study's thread pool) would corrupt each other. One Ipopt solve at a time, process-wide.
  static std::mutex ipopt_mutex;
  const std::lock_guard<std::mutex> lock(ipopt_mutex);
  MinimizerRun run;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetIntegerValue("print_level", options.print_level);
  o.SetStringValue("sb", "yes");  // no banner
  o.SetIntegerValue("max_iter", max_iterations);
  o.SetNumericValue("tol", options.tolerance);
  if (options.max_time_seconds > 0.0) o.SetNumericValue("max_cpu_time", options.max_time_seconds);
  o.SetStringValue("hessian_approximation", options.hessian == "gauss_newton" ? "exact" : "limited-memory");
  // Keep every update (a history as long as the iteration limit, O(iterations p) memory): the quasi-Newton
  // model then learns all of J^T J. On the 33-parameter seed problem Ipopt's default history of 6 needs
  // about 340 iterations, a history of 33 about 160, a full one about 70.
  o.SetIntegerValue("limited_memory_max_history", std::clamp(max_iterations, 6, 1000));
  // The problem is scaled already (variables and cost); Ipopt's gradient-based rescaling would undo it.
  o.SetStringValue("nlp_scaling_method", "none");
  Ipopt::ApplicationReturnStatus status = Ipopt::Invalid_Option;
  if (app->Initialize("") == Ipopt::Solve_Succeeded) {  // "": read no ipopt.opt from the working directory
    const ScaledErrorModel model(*prep.problem, prep.initial, bounds, weighting);
    Ipopt::SmartPtr<ErrorModelNlp> nlp = new ErrorModelNlp(model);
    status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(Ipopt::GetRawPtr(nlp)));
    if (Ipopt::IsValid(app->Statistics())) run.iterations = app->Statistics()->IterationCount();
    *passes += nlp->passes();
    run.parameters_at_bounds = nlp->parameters_at_bounds();
    *x = nlp->solution();
  }
  run.status = StatusOf(status);
  run.message = "Ipopt: " + ReturnName(status);
  run.details = {
      {"hessian", options.hessian}, {"ipopt_status", static_cast<int>(status)}, {"passes_over_data", *passes}};
  return run;
}

}  // namespace

const OptionTable<IpoptOptions>& IpoptOptions::Table() {
  using O = IpoptOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ipopt")
          .Include(ErrorModelEstimatorOptions::Table())
          .Add("hessian", &O::hessian, "gauss_newton or limited_memory (Ipopt's hessian_approximation)",
               OneOf({"gauss_newton", "limited_memory"}))
          .Add("max_iterations", &O::max_iterations, "Ipopt's max_iter", AtLeast(0))
          .Add("tolerance", &O::tolerance, "Ipopt's tol", Positive())
          .Add("max_time_seconds", &O::max_time_seconds, "Ipopt's max_cpu_time, s; 0: none", NonNegative())
          .Add("print_level", &O::print_level, "Ipopt's print_level", Within(0, 12));
  return table;
}

bool IpoptOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

IpoptOptions IpoptOptions::FromYaml(const YAML::Node& node) { return Table().Read(node); }

void IpoptEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                EstimationReport* report) const {
  // Bounds of the first problem, kept by name when identifiability is re-analysed (scaled_error_model.h).
  std::optional<NamedBounds> bounds;
  int passes = 0;
  const auto minimize = [&](const PreparedErrorModel& prep, const RowWeighting& weighting, int budget,
                            Eigen::VectorXd* x) {
    if (!bounds) bounds = BoundsByName(*prep.problem);
    return Minimize(prep, weighting, *bounds, options_, budget, x, &passes);
  };
  EstimateOrSelectErrorModel(name(), options_, options_.max_iterations, minimize, start, controller, data, identified, report);
}

}  // namespace kincal
