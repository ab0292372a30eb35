// The plane kind: a probe ball's centre touching a fixed plane (a touch probe on a table).
//   r = n . p - offset                           (m; one residual: the signed distance to the plane)
// Fixture block (a, b, offset): the normal's tangent coordinates about its start normal n0 and the offset
// (factor.h, FixtureValue): n = w / |w|, w = n0 + a t1 + b t2, a minimal update that keeps n unit.
// dn/da = (I - n n^T) t1 / |w| (likewise b), so dr/da = p . dn/da, dr/d(offset) = -1, dr/dp = n^T.
#include <memory>

#include "estimators/error_model/factor.h"

namespace kincal {
namespace {

class PlaneFactor final : public MeasurementFactor {
 public:
  std::string kind() const override { return "plane"; }
  int Dimension(const Measurement&) const override { return 1; }
  int FixtureSize() const override { return 3; }
  int Evaluate(const Measurement&, const FactorContext&, const PredictedPose& pose, const FixtureValue* fixture,
               Vector6d* residual, Matrix6Xd* jacobian, Matrix6x3d* fixture_jacobian) const override {
    Eigen::Vector3d t1, t2;
    PlaneTangents(fixture->reference, &t1, &t2);
    const Eigen::Vector3d w = fixture->reference + fixture->x[0] * t1 + fixture->x[1] * t2;
    const double w_norm = w.norm();
    const Eigen::Vector3d n = w / w_norm;
    (*residual)[0] = n.dot(pose.p) - fixture->x[2];
    if (jacobian) jacobian->row(0) = n.transpose() * jacobian->topRows<3>();
    if (fixture_jacobian) {
      // p^T (I - n n^T) t / |w|.
      const Eigen::Vector3d q = (pose.p - n * n.dot(pose.p)) / w_norm;
      fixture_jacobian->row(0) << q.dot(t1), q.dot(t2), -1.0;
    }
    return 1;
  }
};

}  // namespace

std::unique_ptr<const MeasurementFactor> NewPlaneFactor() { return std::make_unique<PlaneFactor>(); }

}  // namespace kincal
