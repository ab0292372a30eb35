#pragma once
// `ceres`: the error model (estimators/error_model) minimised by Ceres Solver's Levenberg-Marquardt
// (trust region) on the residual blocks of error_model_cost.h, with analytic derivatives. The linear
// solver is chosen from the problem's structure: DENSE_QR (Householder QR of J: the numerically safest
// for a small dense J) unless rows of different sessions touch different base blocks, where J^T J is
// block sparse and SPARSE_NORMAL_CHOLESKY through SuiteSparse exploits it. Bases, tool and markers are
// placed in closed form and what the data cannot determine is held before solving; options, sequence and
// report (covariance sigma^2 (J^T W J)^-1, held parameters, condition number) are shared with every
// error-model estimator (error_model_estimation.h), so it reads exactly like least_squares'.
#include <string>
#include <vector>

#include "estimators/selection/estimate_or_select.h"
#include "estimators/estimator.h"

namespace kincal {

// The shared keys (error_model, weighting and selection: estimate_or_select.h), then these.
struct CeresOptions : ErrorModelEstimatorOptions {
  // "auto": sparse_normal_cholesky when sessions make J block sparse (and SuiteSparse is available),
  // else dense_qr. Or force one of "dense_qr", "dense_normal_cholesky", "sparse_normal_cholesky".
  std::string linear_solver = "auto";
  int max_iterations = 50;  // Ceres' max_num_iterations (trust-region steps)
  // Ceres' stopping rules: |d cost| <= function_tolerance cost; max_i |g_i| <= gradient_tolerance (g the
  // gradient of half the cost, m^2 per unit of x); |dx| <= parameter_tolerance (|x| + parameter_tolerance).
  // Tight: noise-free data reaches the truth to rounding level, as least_squares does (|x| is about
  // 2 m with a tracker base, so 1e-15 is a few ulps of it).
  double function_tolerance = 1e-14;
  double gradient_tolerance = 1e-16;
  double parameter_tolerance = 1e-15;
  // Levenberg-Marquardt's initial trust region (the inverse of its initial damping, on Ceres' Jacobi-
  // scaled J). Large, as least_squares' initial_damping of 1e-6 is small: the bases are registered in
  // closed form, so Gauss-Newton steps are good from the start (5 iterations instead of Ceres' default
  // 1e4's 8 on the benchmark problem).
  double initial_trust_region_radius = 1e6;
  int num_threads = 1;   // threads evaluating residual blocks
  bool verbose = false;  // Ceres' per-iteration log on stdout

  // Every key, its default, doc and requirement (framework/options.h).
  static const OptionTable<CeresOptions>& Table();
  bool IsValid(std::string* why) const;
  static CeresOptions FromYaml(const YAML::Node& node);
};

class CeresEstimator final : public Estimator {
 public:
  using Options = CeresOptions;

  explicit CeresEstimator(const Options& options = Options()) : options_(options) {}
  std::string name() const override { return "ceres"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

}  // namespace kincal
