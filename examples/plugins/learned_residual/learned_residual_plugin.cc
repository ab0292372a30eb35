// The seed's learned compensation family as a kincal plugin: `learned_residual`
// (learned_residual_estimator.h). Compensation needs no method of its own: the identified robot's forward
// kinematics includes the residual (residual_model.h), so `jacobian` and `analytic_derivative` invert
// model plus residual.
//   kincal --plugin libkincal_learned_residual.so identify --method least_squares,learned_residual ...
#include <memory>

#include "framework/plugin.h"
#include "learned_residual_estimator.h"

KINCAL_PLUGIN(registrar) {
  registrar.AddEstimator(
      "learned_residual",
      "plugin: kernel ridge regression (Gaussian-process mean) of the position residual on the joint angles "
      "(optionally the approach speeds), "
      "on top of the robot it receives; hyper-parameters by cross-validation on the training rows",
      [](const YAML::Node& node) -> std::unique_ptr<kincal::Estimator> {
        bool in_tool_frame = false, with_approach = false;
        const auto options = kincal_learned::ReadLearnedResidualOptions(node, &in_tool_frame, &with_approach);
        return std::make_unique<kincal_learned::LearnedResidualEstimator>(options, in_tool_frame, with_approach);
      });
}
