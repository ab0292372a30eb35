#include "estimators/ceres/ceres_estimator.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <ceres/ceres.h>

#include "estimators/ceres/error_model_cost.h"
#include "framework/units.h"

namespace kincal {
namespace {

bool SuiteSparseAvailable() { return ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE); }

}  // namespace

const OptionTable<CeresOptions>& CeresOptions::Table() {
  using O = CeresOptions;
  const Requirement<std::string> solver = [](const std::string& name) -> std::string {
    const std::string why = OneOf({"auto", "dense_qr", "dense_normal_cholesky", "sparse_normal_cholesky"})(name);
    if (!why.empty()) return why;
    if (name == "sparse_normal_cholesky" && !SuiteSparseAvailable()) return "needs SuiteSparse, which this Ceres lacks";
    return "";
  };
  static const OptionTable<O> table =
      OptionTable<O>("ceres")
          .Include(ErrorModelEstimatorOptions::Table())
          .Add("linear_solver", &O::linear_solver, "auto, dense_qr, dense_normal_cholesky or sparse_normal_cholesky",
               solver)
          .Add("max_iterations", &O::max_iterations, "Ceres' max_num_iterations", AtLeast(0))
          .Add("function_tolerance", &O::function_tolerance, "Ceres' function_tolerance", NonNegative())
          .Add("gradient_tolerance", &O::gradient_tolerance, "Ceres' gradient_tolerance", NonNegative())
          .Add("parameter_tolerance", &O::parameter_tolerance, "Ceres' parameter_tolerance", NonNegative())
          .Add("initial_trust_region_radius", &O::initial_trust_region_radius,
               "Levenberg-Marquardt's initial trust region", Positive())
          .Add("num_threads", &O::num_threads, "threads evaluating residual blocks", AtLeast(1))
          .Add("verbose", &O::verbose, "Ceres' per-iteration log on stdout");
  return table;
}

bool CeresOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

CeresOptions CeresOptions::FromYaml(const YAML::Node& node) { return Table().Read(node); }

namespace {

EstimationStatus StatusOf(const ceres::Solver::Summary& summary) {
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS:
      return EstimationStatus::kConverged;
    case ceres::NO_CONVERGENCE:
      return EstimationStatus::kIterationLimit;
    case ceres::FAILURE:
    case ceres::USER_FAILURE:
      return EstimationStatus::kFailed;
  }
  return EstimationStatus::kFailed;
}

// Minimises from *x (the problem's parameters) with up to max_iterations steps; *x ends at the solution.
ceres::Solver::Summary Minimize(const ErrorModelProblem& problem, const CeresOptions& options,
                                const RowWeighting& weighting, int max_iterations, Eigen::VectorXd* x,
                                std::vector<std::string>* warnings) {
  CeresErrorModel model(problem, weighting, *x);
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  std::string solver = options.linear_solver;
  if (solver == "auto") {
    solver = model.sessions_make_it_sparse() && SuiteSparseAvailable() ? "sparse_normal_cholesky" : "dense_qr";
    const std::string warning = "ceres: SuiteSparse is not available; the sparse session problem is solved densely";
    if (model.sessions_make_it_sparse() && !SuiteSparseAvailable() &&
        std::find(warnings->begin(), warnings->end(), warning) == warnings->end()) {
      warnings->push_back(warning);
    }
  }
  if (solver == "dense_qr") so.linear_solver_type = ceres::DENSE_QR;
  if (solver == "dense_normal_cholesky") so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  if (solver == "sparse_normal_cholesky") {
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  }
  so.max_num_iterations = max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.num_threads = options.num_threads;
  so.initial_trust_region_radius = options.initial_trust_region_radius;
  so.minimizer_progress_to_stdout = options.verbose;
  so.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &model.problem(), &summary);
  *x = model.x();
  return summary;
}

}  // namespace

void CeresEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                EstimationReport* report) const {
  // Totals over the solves (a second one follows when identifiability changes at the first solution).
  int successful = 0, unsuccessful = 0;
  std::map<std::string, double> seconds;
  const auto minimize = [&](const PreparedErrorModel& prep, const RowWeighting& weighting, int budget,
                            Eigen::VectorXd* x) {
    const ceres::Solver::Summary s = Minimize(*prep.problem, options_, weighting, budget, x, &report->warnings);
    successful += s.num_successful_steps;
    unsuccessful += s.num_unsuccessful_steps;
    seconds["total"] += s.total_time_in_seconds;
    seconds["preprocessor"] += s.preprocessor_time_in_seconds;
    seconds["minimizer"] += s.minimizer_time_in_seconds;
    seconds["residual_evaluation"] += s.residual_evaluation_time_in_seconds;
    seconds["jacobian_evaluation"] += s.jacobian_evaluation_time_in_seconds;
    seconds["linear_solver"] += s.linear_solver_time_in_seconds;
    seconds["postprocessor"] += s.postprocessor_time_in_seconds;
    MinimizerRun run;
    run.status = StatusOf(s);
    run.message = s.message;
    run.iterations = s.num_successful_steps + s.num_unsuccessful_steps;
    run.details = {{"linear_solver", ceres::LinearSolverTypeToString(s.linear_solver_type_used)},
                   {"successful_steps", successful},
                   {"unsuccessful_steps", unsuccessful},
                   {"times_s", seconds}};
    return run;
  };
  EstimateOrSelectErrorModel(name(), options_, options_.max_iterations, minimize, start, controller, data, identified, report);
}

}  // namespace kincal
