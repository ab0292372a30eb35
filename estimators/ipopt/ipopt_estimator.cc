#include "estimators/ipopt/ipopt_estimator.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpSolveStatistics.hpp>

#include "estimators/ipopt/error_model_nlp.h"

namespace kincal {
namespace {

std::string ReturnName(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "solved";
    case Ipopt::Solved_To_Acceptable_Level: return "solved to the acceptable level";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "search direction became too small";
    case Ipopt::Diverging_Iterates: return "diverging iterates";
    case Ipopt::User_Requested_Stop: return "stopped by the user";
    case Ipopt::Maximum_Iterations_Exceeded: return "iteration limit reached";
    case Ipopt::Maximum_CpuTime_Exceeded: return "time limit reached";
    case Ipopt::Restoration_Failed: return "restoration failed";
    case Ipopt::Error_In_Step_Computation: return "error in step computation";
    case Ipopt::Invalid_Number_Detected: return "invalid number detected (non-finite cost)";
    default: return "return status " + std::to_string(static_cast<int>(s));
  }
}

EstimationStatus StatusOf(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level: return EstimationStatus::kConverged;
    case Ipopt::Maximum_Iterations_Exceeded:
    case Ipopt::Maximum_CpuTime_Exceeded: return EstimationStatus::kIterationLimit;
    default: return EstimationStatus::kFailed;
  }
}

struct IpoptRun {
  Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;
  int iterations = 0;
  int passes = 0;
  int parameters_at_bounds = 0;
};

// Minimises from the prepared problem's start within the bounds (`bounds` by name, see
// scaled_error_model.h); *x ends at Ipopt's final point.
IpoptRun Minimize(const PreparedErrorModel& prep, const NamedBounds& bounds, const IpoptOptions& options,
                  int max_iterations, Eigen::VectorXd* x) {
  // Debian's Ipopt 3.11 solves its linear systems with sequential MUMPS, whose state is global: two solves
  // at once (a study's thread pool) would corrupt each other. One Ipopt solve at a time, process-wide.
  static std::mutex ipopt_mutex;
  const std::lock_guard<std::mutex> lock(ipopt_mutex);
  IpoptRun run;
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
  if (app->Initialize("") != Ipopt::Solve_Succeeded) {  // "": read no ipopt.opt from the working directory
    run.status = Ipopt::Invalid_Option;
    return run;
  }
  const ScaledErrorModel model(*prep.problem, prep.initial, bounds);
  Ipopt::SmartPtr<ErrorModelNlp> nlp = new ErrorModelNlp(model);
  run.status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(Ipopt::GetRawPtr(nlp)));
  if (Ipopt::IsValid(app->Statistics())) run.iterations = app->Statistics()->IterationCount();
  run.passes = nlp->passes();
  run.parameters_at_bounds = nlp->parameters_at_bounds();
  *x = nlp->solution();
  return run;
}

}  // namespace

bool IpoptOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (!error_model.IsValid(why)) return false;
  if (hessian != "gauss_newton" && hessian != "limited_memory") {
    return fail("hessian must be gauss_newton or limited_memory, got '" + hessian + "'");
  }
  if (max_iterations < 0) return fail("max_iterations must be >= 0");
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) return fail("tolerance must be positive");
  if (!(max_time_seconds >= 0.0) || !std::isfinite(max_time_seconds)) return fail("max_time_seconds must be >= 0");
  if (print_level < 0 || print_level > 12) return fail("print_level must be within 0..12");
  return true;
}

IpoptOptions IpoptOptions::FromYaml(const YAML::Node& node) {
  IpoptOptions o;
  OptionsReader reader(node, "ipopt");
  o.error_model.Read(&reader);
  reader.Get("hessian", &o.hessian);
  reader.Get("max_iterations", &o.max_iterations);
  reader.Get("tolerance", &o.tolerance);
  reader.Get("max_time_seconds", &o.max_time_seconds);
  reader.Get("print_level", &o.print_level);
  reader.Finish();
  return o;
}

void IpoptEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                EstimationReport* report) const {
  PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options_.error_model);
  if (FinishIfNothingFree(prep, identified, report)) return;
  Eigen::VectorXd x = prep.problem->InitialX();
  const double initial_cost = prep.initial.cost;
  const NamedBounds bounds = BoundsByName(*prep.problem);
  IpoptRun run = Minimize(prep, bounds, options_, options_.max_iterations, &x);
  int iterations = run.iterations, passes = run.passes;
  if (StatusOf(run.status) == EstimationStatus::kConverged && ReanalyzeIdentifiability(x, RowWeighting(), &prep, &x)) {
    run = Minimize(prep, bounds, options_, std::max(0, options_.max_iterations - iterations), &x);
    iterations += run.iterations;
    passes += run.passes;
  }
  report->status = StatusOf(run.status);
  report->message = "Ipopt: " + ReturnName(run.status);
  report->iterations = iterations;
  FinishErrorModel(prep, x, RowWeighting(), identified, report);
  nlohmann::json& d = report->details;
  d["hessian"] = options_.hessian;
  d["ipopt_status"] = static_cast<int>(run.status);
  d["passes_over_data"] = passes;
  d["initial_cost_m2"] = initial_cost;
  ReportParametersAtBounds("ipopt", run.parameters_at_bounds, report);
}

}  // namespace kincal
