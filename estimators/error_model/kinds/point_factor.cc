// The point kind: a tracker's 3-D point, a 6-D pose where the row has an orientation, and a partial
// point (only the axes the row measures: m.axes).
//   r[0..2] = p - p_measured                      (m, measurement frame of the row's session)
//   r[3..5] = L log(R R_measured^T)               (rows with an orientation; L = orientation_length, m/rad)
// The rotation residual's rate is Jl^-1(phi) times R's angular velocity (pose_jacobians.h).
#include <memory>

#include "estimators/error_model/factor.h"
#include "estimators/error_model/pose_jacobians.h"

namespace kincal {
namespace {

class PointFactor final : public MeasurementFactor {
 public:
  std::string kind() const override { return "point"; }
  int Dimension(const Measurement& m) const override {
    return m.orientation ? 6 : static_cast<int>(m.axes[0]) + static_cast<int>(m.axes[1]) + static_cast<int>(m.axes[2]);
  }
  int Evaluate(const Measurement& m, const FactorContext& context, const PredictedPose& pose, const FixtureValue*,
               Vector6d* residual, Matrix6Xd* jacobian, Matrix6x3d*) const override {
    if (!(m.axes[0] && m.axes[1] && m.axes[2])) return Partial(m, pose, residual, jacobian);
    residual->head<3>() = pose.p - m.p;
    if (!m.orientation) return 3;
    const Eigen::Vector3d phi = RotationLog(pose.R * m.orientation->toRotationMatrix().transpose());
    residual->tail<3>() = context.orientation_length * phi;
    if (jacobian && jacobian->cols() > 0) {
      const Eigen::Matrix3d map = context.orientation_length * LeftJacobianInverseSO3(phi);
      jacobian->bottomRows<3>() = map * jacobian->bottomRows<3>();
    }
    return 6;
  }

 private:
  // A partial point (a gauge, a table of known height): the measured axes only, in x, y, z order. Row k
  // of the result is axis a >= k of the pose Jacobian, so copying forward in place is safe.
  static int Partial(const Measurement& m, const PredictedPose& pose, Vector6d* residual, Matrix6Xd* jacobian) {
    int k = 0;
    for (int a = 0; a < 3; ++a) {
      if (!m.axes[a]) continue;
      (*residual)[k] = pose.p[a] - m.p[a];
      if (jacobian && k != a) jacobian->row(k) = jacobian->row(a);
      ++k;
    }
    return k;
  }
};

}  // namespace

std::unique_ptr<const MeasurementFactor> NewPointFactor() { return std::make_unique<PointFactor>(); }

}  // namespace kincal
