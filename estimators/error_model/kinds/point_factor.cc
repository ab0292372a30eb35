// The point kind: a tracker's 3-D point, and a 6-D pose where the row has an orientation.
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
  int Dimension(const Measurement& m) const override { return m.orientation ? 6 : 3; }
  int Evaluate(const Measurement& m, const FactorContext& context, const PredictedPose& pose, const FixtureValue*,
               Vector6d* residual, Matrix6Xd* jacobian, Matrix6x3d*) const override {
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
};

}  // namespace

std::unique_ptr<const MeasurementFactor> NewPointFactor() { return std::make_unique<PointFactor>(); }

}  // namespace kincal
