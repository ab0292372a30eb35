#pragma once
// The `ratio_regression` estimator: each joint's actual reduction ratio from its sweep (METHOD.md 3).
//
// Per swept joint: the axis is refitted from the arc (geometric/arc_fit.h, the same fit the geometric
// estimator uses), each stop's actual angle measured about it, and regressed on the motor angle the
// encoder counts give, 2 pi counts / counts_per_rev. Stated with the drive variable x = the joint angle
// the start robot's ratio gives the counts (geometric/sweeps.h), the fit is phi = c + s x with
// s = K_start / K_actual, so K = K_start / s. The paper regresses motor angle on actual angle (its
// eq. theta_e = K theta_a + c); here the noisy quantity, the measured angle, is the response and the
// exact one, the counts, the regressor, which keeps the slope free of errors-in-variables attenuation.
// Without counts in the rows the motor angle is the one the controller commanded, K_controller q.
//
// Writes drives.ratio and nothing else: joint offsets (theta) are referenced to the encoder zero, which a
// new ratio does not move (the geometric stage measures them so, geometric_solver.h).
//
// Works alone (after `none`) or as the second stage of `geometric,ratio_regression`. Joints never swept
// keep their ratio, with a warning.
#include <string>

#include "estimators/geometric/arc_fit.h"
#include "estimators/geometric/uncertainty.h"
#include "estimators/estimator.h"

namespace kincal {

class RatioRegressionEstimator final : public Estimator {
 public:
  // Standard deviations: the keys stddev, bootstrap_samples, bootstrap_seed (geometric/uncertainty.h).
  struct Options : geometric::UncertaintyOptions {
    // Arc fit (circle_fit, min_spread, min_curvature_ratio, max_iterations), as the geometric estimator.
    geometric::ArcFitOptions arc;
    std::string marker;  // as the geometric estimator

    // Every key, its default, doc and requirement (framework/options.h).
    static const OptionTable<Options>& Table();
    bool IsValid(std::string* why) const;
    static Options FromYaml(const YAML::Node& node);
  };

  RatioRegressionEstimator() : RatioRegressionEstimator(Options()) {}
  explicit RatioRegressionEstimator(const Options& options) : options_(options) {}
  std::string name() const override { return "ratio_regression"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

}  // namespace kincal
