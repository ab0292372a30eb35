// The distance kind: a ballbar's or a cable's length from a fixed pivot c to the marker (DynaCal-type).
//   r = |p - c| - d_measured                     (m; one residual)
// Fixture block: the pivot c (3, m, measurement frame of session 0). dr/dp = u^T, dr/dc = -u^T with
// u = (p - c) / |p - c|; a marker on the pivot (|p - c| = 0) has no direction: u = 0 there.
#include <memory>

#include "estimators/error_model/factor.h"

namespace kincal {
namespace {

class DistanceFactor final : public MeasurementFactor {
 public:
  std::string kind() const override { return "distance"; }
  int Dimension(const Measurement&) const override { return 1; }
  int FixtureSize() const override { return 3; }
  int Evaluate(const Measurement& m, const FactorContext&, const PredictedPose& pose, const FixtureValue* fixture,
               Vector6d* residual, Matrix6Xd* jacobian, Matrix6x3d* fixture_jacobian) const override {
    const Eigen::Vector3d v = pose.p - fixture->x;
    const double length = v.norm();
    (*residual)[0] = length - m.distance;
    const Eigen::Vector3d u = length > 0.0 ? Eigen::Vector3d(v / length) : Eigen::Vector3d::Zero();
    if (jacobian) jacobian->row(0) = u.transpose() * jacobian->topRows<3>();
    if (fixture_jacobian) fixture_jacobian->row(0) = -u.transpose();
    return 1;
  }
};

}  // namespace

std::unique_ptr<const MeasurementFactor> NewDistanceFactor() { return std::make_unique<DistanceFactor>(); }

}  // namespace kincal
