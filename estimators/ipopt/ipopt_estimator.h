#pragma once
// `ipopt`: the error model (estimators/error_model) minimised by Ipopt (Waechter & Biegler, "On the
// implementation of an interior-point filter line-search algorithm for large-scale nonlinear
// programming", Math. Prog. 106, 2006) within bounds on every parameter. The cost is the weighted sum
// f(x) = sum_i w_i rho(|r_i(x)|^2) with its exact gradient 2 J^T W r; the Hessian is either the
// Gauss-Newton matrix 2 J^T W J (IRLS with a robust loss; without one the exact Hessian less
// sum_k r_k Hess(r_k), which vanishes with the
// residuals: quadratic convergence on calibration data, about 10 iterations) or Ipopt's quasi-Newton
// BFGS in compact limited-memory form (with a history as long as the iteration limit, so that it keeps
// every update: about 70 iterations). All are accumulated row by row (normal_equations.h): memory does
// not grow with the poses. As for `nlopt`, Ipopt sees scaled variables and cost within bounds on every
// parameter (estimators/bounded/scaled_error_model.h); bases, tool and markers are placed in closed form
// (bounds centred on that start) and what the data cannot determine is held before solving; options,
// sequence and report are shared with every error-model estimator (error_model_estimation.h).
//
// Ipopt 3.11's C++ TNLP interface; the linear solver is the one Ipopt was built with (MUMPS on Debian).
// Ipopt's console output is silenced unless print_level > 0. MUMPS (sequential) keeps global state: do not
// run two `ipopt` estimations in parallel threads.
#include <string>

#include "estimators/selection/estimate_or_select.h"
#include "estimators/estimator.h"

namespace kincal {

// The shared keys (error_model, bounds included, weighting and selection: estimate_or_select.h), then these.
struct IpoptOptions : ErrorModelEstimatorOptions {
  std::string hessian = "gauss_newton";  // or "limited_memory" (Ipopt's hessian_approximation)
  int max_iterations = 200;              // Ipopt's max_iter
  // Ipopt's tol: the largest scaled optimality error (dual infeasibility in y, complementarity) at which
  // it stops. The cost is in units of its curvature, so 1e-12 puts the solution within about 1e-12
  // characteristic scales (1e-15 m) of the minimum.
  double tolerance = 1e-12;
  double max_time_seconds = 0.0;  // Ipopt's max_cpu_time; 0: no limit
  int print_level = 0;            // Ipopt's print_level, 0..12; 0 prints nothing (not even the banner)

  // Every key, its default, doc and requirement (framework/options.h).
  static const OptionTable<IpoptOptions>& Table();
  bool IsValid(std::string* why) const;
  static IpoptOptions FromYaml(const YAML::Node& node);
};

class IpoptEstimator final : public Estimator {
 public:
  using Options = IpoptOptions;

  explicit IpoptEstimator(const Options& options = Options()) : options_(options) {}
  std::string name() const override { return "ipopt"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

}  // namespace kincal
