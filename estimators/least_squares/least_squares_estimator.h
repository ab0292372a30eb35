#pragma once
// `least_squares`: the error model (estimators/error_model) minimised by our own Levenberg-Marquardt
// with analytic Jacobians (Marquardt 1963 with the diagonal scaling of J^T J; Nielsen's damping update,
// "Damping parameter in Marquardt's method", IMM-REP-1999-05). Each iteration is one pass over the data
// that accumulates cost, J^T W r and J^T W J row by row (normal_equations.h), so memory is O(p^2)
// whatever the number of poses. A robust loss (Huber, Cauchy) enters by iteratively reweighted least
// squares, per-row weights as given. Bases, tool and markers are placed in closed form and parameters the
// data cannot determine are held before solving; options, sequence and report are shared with every
// error-model estimator (error_model_estimation.h).
#include <string>
#include <vector>

#include "estimators/selection/estimate_or_select.h"
#include "estimators/estimator.h"

namespace kincal {

// The shared keys (error_model, weighting and selection: estimate_or_select.h), then these.
struct LeastSquaresOptions : ErrorModelEstimatorOptions {
  int max_iterations = 50;  // passes over the data that propose a step
  // Stop when an accepted step changes no parameter by more than parameter_tolerance times its
  // characteristic scale (1 mm, 1 mrad, 1e-3 ratio scale): 1e-8 is 10 pm, below any instrument.
  double parameter_tolerance = 1e-8;
  // Stop when an accepted step lowers the cost by less than this fraction of it.
  double function_tolerance = 1e-14;
  // Stop when every column of J is orthogonal to the residuals to within this cosine.
  double gradient_tolerance = 1e-12;
  // Initial damping lambda of (J^T W J + lambda diag(J^T W J)) dx = -J^T W r. Small: the bases are
  // registered in closed form, so Gauss-Newton steps are good from the start.
  double initial_damping = 1e-6;

  // Every key, its default, doc and requirement (framework/options.h).
  static const OptionTable<LeastSquaresOptions>& Table();
  bool IsValid(std::string* why) const;
  static LeastSquaresOptions FromYaml(const YAML::Node& node);
};

class LeastSquaresEstimator final : public Estimator {
 public:
  using Options = LeastSquaresOptions;

  explicit LeastSquaresEstimator(const Options& options = Options()) : options_(options) {}
  std::string name() const override { return "least_squares"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

}  // namespace kincal
