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
  LearnedResidualEstimator(const KernelRidgeOptions& options, bool in_tool_frame)
      : options_(options), in_tool_frame_(in_tool_frame) {}
  std::string name() const override { return "learned_residual"; }

 private:
  void DoEstimate(const kincal::Robot& start, const kincal::Robot& controller, const kincal::Dataset& data,
                  kincal::Robot* identified, kincal::EstimationReport* report) const override;

  KernelRidgeOptions options_;
  bool in_tool_frame_;
};

// Options (YAML): kernel (squared_exponential, matern52), frame (base, tool), folds, seed, ard_rounds,
// length_scales (rad) and lambdas (the grid). Throws std::invalid_argument for bad ones.
KernelRidgeOptions ReadLearnedResidualOptions(const YAML::Node& node, bool* in_tool_frame);

}  // namespace kincal_learned
