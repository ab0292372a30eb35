#include "estimators/least_squares/least_squares_estimator.h"

#include <cmath>
#include <cstdio>
#include <memory>

#include <Eigen/Cholesky>

#include "framework/units.h"

namespace kincal {

const OptionTable<LeastSquaresOptions>& LeastSquaresOptions::Table() {
  using O = LeastSquaresOptions;
  static const OptionTable<O> table =
      OptionTable<O>("least_squares")
          .Include(ErrorModelEstimatorOptions::Table())
          .Add("max_iterations", &O::max_iterations, "passes over the data that propose a step", AtLeast(0))
          .Add("parameter_tolerance", &O::parameter_tolerance,
               "stop when a step changes no parameter by more than this times its scale", Positive())
          .Add("function_tolerance", &O::function_tolerance,
               "stop when a step lowers the cost by less than this fraction", NonNegative())
          .Add("gradient_tolerance", &O::gradient_tolerance,
               "stop when every column of J is orthogonal to the residuals within this cosine", NonNegative())
          .Add("initial_damping", &O::initial_damping, "initial Levenberg-Marquardt damping", NonNegative());
  return table;
}

bool LeastSquaresOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

LeastSquaresOptions LeastSquaresOptions::FromYaml(const YAML::Node& node) { return Table().Read(node); }

namespace {

// Largest |cos| between a column of J and the residual vector: |(J^T r)_j| / (|J_j| |r|).
double GradientCosine(const NormalEquations& ne) {
  const double r_norm = std::sqrt(ne.irls_squares);
  if (!(r_norm > 0.0)) return 0.0;
  double worst = 0.0;
  for (int j = 0; j < ne.Jtr.size(); ++j) {
    const double c = std::sqrt(ne.JtJ(j, j));
    if (c > 0.0) worst = std::max(worst, std::abs(ne.Jtr[j]) / (c * r_norm));
  }
  return worst;
}

struct LmResult {
  EstimationStatus status = EstimationStatus::kIterationLimit;
  std::string message = "iteration limit reached";
  int iterations = 0;
  double lambda = 0.0;
  bool fresh = false;  // *ne comes from a pass at the final x (not the normal equations it started with)
};

// Levenberg-Marquardt from *x, where *ne holds the normal equations; both end at the solution.
LmResult Minimize(const ErrorModelProblem& problem, const LeastSquaresOptions& options, const RowWeighting& weighting,
                  int max_iterations, Eigen::VectorXd* x, NormalEquations* ne) {
  LmResult out;
  const Eigen::VectorXd scale = problem.CharacteristicScales();
  const int p = problem.num_parameters();
  double lambda = options.initial_damping;
  double nu = 2.0;
  if (p == 0) {
    out.status = EstimationStatus::kConverged;
    out.message = "no free parameter";
    return out;
  }
  while (out.iterations < max_iterations) {
    if (ne->cost == 0.0 || GradientCosine(*ne) <= options.gradient_tolerance) {
      out.status = EstimationStatus::kConverged;
      out.message = ne->cost == 0.0 ? "zero residual" : "gradient tolerance reached";
      break;
    }
    ++out.iterations;
    // Marquardt: damp each parameter in proportion to its own curvature, so units do not matter.
    const Eigen::VectorXd D = ne->JtJ.diagonal().cwiseMax(1e-300);
    Eigen::MatrixXd A = ne->JtJ;
    A.diagonal() += lambda * D;
    const Eigen::VectorXd d_inv = D.cwiseSqrt().cwiseInverse();
    const Eigen::LLT<Eigen::MatrixXd> llt(d_inv.asDiagonal() * A * d_inv.asDiagonal());
    if (llt.info() != Eigen::Success) {
      lambda = std::max(lambda * nu, 1e-12);
      nu *= 2.0;
      continue;
    }
    const Eigen::VectorXd dx = -(d_inv.asDiagonal() * llt.solve(d_inv.asDiagonal() * ne->Jtr)).eval();
    const double step = dx.cwiseQuotient(scale).cwiseAbs().maxCoeff();
    // Decrease of the cost predicted by the linearised model: -(2 dx.g + dx^T N dx).
    const double predicted = -(2.0 * dx.dot(ne->Jtr) + dx.dot(ne->JtJ * dx));
    const Eigen::VectorXd x_new = *x + dx;
    NormalEquations ne_new = AccumulateNormalEquations(problem, x_new, weighting);
    const double actual = ne->cost - ne_new.cost;
    if (actual > 0.0 && std::isfinite(ne_new.cost)) {
      const double rho = predicted > 0.0 ? actual / predicted : 1.0;
      const double old_cost = ne->cost;
      *x = x_new;
      *ne = std::move(ne_new);
      out.fresh = true;
      lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      nu = 2.0;
      if (step <= options.parameter_tolerance) {
        out.status = EstimationStatus::kConverged;
        out.message = "parameter tolerance reached";
        break;
      }
      if (actual <= options.function_tolerance * old_cost) {
        out.status = EstimationStatus::kConverged;
        out.message = "function tolerance reached";
        break;
      }
    } else {
      // No decrease: the cost is at its rounding level when the step is already negligible.
      if (step <= options.parameter_tolerance || std::abs(actual) <= 1e-15 * ne->cost) {
        out.status = EstimationStatus::kConverged;
        out.message = "no further decrease (cost at rounding level)";
        break;
      }
      lambda = std::max(lambda * nu, 1e-12);
      nu *= 2.0;
      if (lambda > 1e16) {
        out.status = EstimationStatus::kFailed;
        out.message = "the damping grew without a decrease of the cost";
        break;
      }
    }
  }
  out.lambda = lambda;
  return out;
}

}  // namespace

void LeastSquaresEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data,
                                       Robot* identified, EstimationReport* report) const {
  const auto minimize = [&](const PreparedErrorModel& prep, const RowWeighting& weighting, int budget,
                            Eigen::VectorXd* x) {
    NormalEquations ne = prep.initial;
    const LmResult lm = Minimize(*prep.problem, options_, weighting, budget, x, &ne);
    MinimizerRun run;
    run.status = lm.status;
    run.message = lm.message;
    run.iterations = lm.iterations;
    run.details = {{"final_damping", lm.lambda}};
    if (lm.fresh) run.normal_equations = std::make_shared<const NormalEquations>(std::move(ne));
    return run;
  };
  EstimateOrSelectErrorModel(name(), options_, options_.max_iterations, minimize, start, controller, data, identified, report);
}

}  // namespace kincal
