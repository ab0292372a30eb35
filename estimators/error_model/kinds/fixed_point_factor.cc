// The fixed-point kind: the marker (a sphere's centre) seated in a fixed socket c, in any orientation.
//   r = p - c                                    (m; three residuals, measurement frame of the session)
// Fixture block: the point c (3, m, measurement frame of session 0); dr/dp = I, dr/dc = -I.
#include <memory>

#include "estimators/error_model/factor.h"

namespace kincal {
namespace {

class FixedPointFactor final : public MeasurementFactor {
 public:
  std::string kind() const override { return "fixed_point"; }
  int Dimension(const Measurement&) const override { return 3; }
  int FixtureSize() const override { return 3; }
  int Evaluate(const Measurement&, const FactorContext&, const PredictedPose& pose, const FixtureValue* fixture,
               Vector6d* residual, Matrix6Xd*, Matrix6x3d* fixture_jacobian) const override {
    residual->head<3>() = pose.p - fixture->x;
    if (fixture_jacobian) fixture_jacobian->topRows<3>() = -Eigen::Matrix3d::Identity();
    return 3;
  }
};

}  // namespace

std::unique_ptr<const MeasurementFactor> NewFixedPointFactor() { return std::make_unique<FixedPointFactor>(); }

}  // namespace kincal
