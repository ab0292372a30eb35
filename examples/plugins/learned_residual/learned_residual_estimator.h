#pragma once
// learned_residual: an estimator that runs after any other (a pipeline: `least_squares,learned_residual`)
// and adds to the robot it receives a kernel ridge regression of the position residual on the actual joint
// angles (kernel_ridge.h, residual_model.h), hyper-parameters by cross-validation on the rows it is given.
#include <string>

#include "estimators/estimator.h"
#include "kernel_ridge.h"

namespace kincal_learned {

class LearnedResidualEstimator final : public kincal::Estimator {
 public:
  // in_tool_frame: the residual regressed in the tool frame, else in the robot's base frame.
  // with_approach: the residual a function of the joint readings and the approach features, as a
  // joint-level correction (approach_residual.h), else of the actual joint angles inside the model
  // (residual_model.h).
  LearnedResidualEstimator(const KernelRidgeOptions& options, bool in_tool_frame, bool with_approach = false)
      : options_(options), in_tool_frame_(in_tool_frame), with_approach_(with_approach) {}
  std::string name() const override { return "learned_residual"; }

 private:
  void DoEstimate(const kincal::Robot& start, const kincal::Robot& controller, const kincal::Dataset& data,
                  kincal::Robot* identified, kincal::EstimationReport* report) const override;

  // The joint-level variant (with_approach).
  void EstimateWithApproach(const kincal::Robot& start, const kincal::Robot& controller, const kincal::Dataset& data,
                            kincal::Robot* identified, kincal::EstimationReport* report) const;

  KernelRidgeOptions options_;
  bool in_tool_frame_;
  bool with_approach_;
};

// Options (YAML): features (joints: the actual joint angles, the default; joints_and_approach: the
// readings and the approach speeds, approach_residual.h), kernel (squared_exponential, matern52), frame
// (base, tool; joints only), folds, seed, ard_rounds, length_scales (rad, or spreads for the approach
// speeds) and lambdas (the grid). Throws std::invalid_argument for bad ones.
KernelRidgeOptions ReadLearnedResidualOptions(const YAML::Node& node, bool* in_tool_frame,
                                              bool* with_approach = nullptr);

}  // namespace kincal_learned
