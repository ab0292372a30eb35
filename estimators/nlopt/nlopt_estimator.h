#pragma once
// `nlopt`: the error model (estimators/error_model) minimised by NLopt (S. G. Johnson, "The NLopt
// nonlinear-optimization package") within bounds on every parameter. The cost is the weighted sum
// f(x) = sum_i w_i rho(|r_i(x)|^2) with its exact gradient 2 J^T W r, accumulated row by row
// (normal_equations.h), so memory does not grow with the poses. The optimiser sees scaled variables and
// cost (O(1) numbers whatever the units) within bounds on every parameter (ErrorModelBounds around the
// registered start, kept when identifiability is re-analysed): estimators/bounded/scaled_error_model.h.
// Bases, tool and markers are placed in closed form (bounds centred on that start) and what the data
// cannot determine is held before solving; options, sequence and report are shared with every
// error-model estimator (error_model_estimation.h), a robust loss and row weights included.
//
// Algorithm by name. Default LD_SLSQP (Kraft 1988: sequential quadratic programming with a dense BFGS
// Hessian, bound constraints handled exactly in its QP). Measured on the benchmark problem (1000 poses,
// 33 free parameters, bench/error_model_bench.cc): SLSQP reaches the least-squares minimum to rounding
// level on noise-free data and to 1e-9 of a standard deviation on noisy data in about 100 evaluations;
// LD_LBFGS and LD_VAR2 stop after 80-130 evaluations on Luksan's own criteria, 1e-4 of a standard
// deviation and a few nm of residual short of the minimum; LD_MMA and LD_CCSAQ need 900-1700; LN_BOBYQA
// (Powell 2009, derivative-free, bounded) 5000-7700. A few dozen parameters make SLSQP's dense
// quasi-Newton model cheap, and it learns the whole J^T J, where limited-memory and first-order methods
// crawl along the ill-conditioned directions of a calibration Jacobian.
#include <string>

#include "estimators/selection/estimate_or_select.h"
#include "estimators/estimator.h"

namespace kincal {

// The shared keys (error_model, bounds included, weighting and selection: estimate_or_select.h), then these.
struct NloptOptions : ErrorModelEstimatorOptions {
  // An NLopt local algorithm that honours bounds: LD_SLSQP, LD_LBFGS, LD_MMA, LD_CCSAQ, LD_VAR1, LD_VAR2,
  // LD_TNEWTON, LD_TNEWTON_PRECOND_RESTART (gradient-based, exact gradients), LN_BOBYQA, LN_COBYLA,
  // LN_NEWUOA_BOUND, LN_NELDERMEAD, LN_SBPLX (derivative-free).
  std::string algorithm = "LD_SLSQP";
  // Cost (and gradient) evaluations, each a pass over the data. SLSQP needs about 100; the derivative-free
  // BOBYQA about 250 per free parameter.
  int max_evaluations = 20000;
  double max_time_seconds = 0.0;  // 0: no limit
  // Stop when a step changes the cost by less than this fraction of it (NLopt ftol_rel).
  double function_tolerance = 1e-15;
  // Stop when a step changes every scaled variable by less than this (NLopt xtol_abs on y; 1 = one
  // characteristic scale, so 1e-12 is 1 fm / 1 frad).
  double parameter_tolerance = 1e-12;

  // Every key, its default, doc and requirement (framework/options.h).
  static const OptionTable<NloptOptions>& Table();
  bool IsValid(std::string* why) const;
  static NloptOptions FromYaml(const YAML::Node& node);
};

class NloptEstimator final : public Estimator {
 public:
  using Options = NloptOptions;

  explicit NloptEstimator(const Options& options = Options()) : options_(options) {}
  std::string name() const override { return "nlopt"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

}  // namespace kincal
