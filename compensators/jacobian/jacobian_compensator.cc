#include "compensators/jacobian/jacobian_compensator.h"

#include <cmath>

#include "framework/math.h"
#include "models/chain_model.h"

namespace kincal {
namespace {

class TwistResidual final : public PoseResidual {
 public:
  TwistResidual(const KinematicModel& model, const CompensationTarget& target, double length_scale)
      : model_(model),
        T_a_(target.T_meas_tool),
        position_only_(!target.has_orientation),
        inverse_scale_(1.0 / length_scale) {}

  void Evaluate(const Eigen::VectorXd& q, Eigen::VectorXd* r, double* position_error,
                double* orientation_error) const override {
    // The Jacobian comes from the same pass; Linearize takes it when asked at these joints (after
    // an accepted step, as the iteration does).
    const Eigen::Isometry3d T_c = PoseAndJointJacobian(model_, q, &J_);
    q_ = q;
    const Eigen::Vector3d dp = T_a_.translation() - T_c.translation();
    *position_error = dp.norm();
    if (position_only_) {
      *r = dp * inverse_scale_;
      *orientation_error = 0.0;
      return;
    }
    r->resize(6);
    r->head<3>() = dp * inverse_scale_;
    r->tail<3>() = RotationLog(T_a_.linear() * T_c.linear().transpose());
    *orientation_error = r->tail<3>().norm();
  }

  void Linearize(const Eigen::VectorXd& q, Eigen::MatrixXd* A) const override {
    if (!(q_.size() == q.size() && q_ == q)) {
      J_ = model_.JointJacobian(q);
      q_ = q;
    }
    const Matrix6Xd& J = J_;
    if (position_only_) {
      *A = J.topRows<3>() * inverse_scale_;
      return;
    }
    *A = J;
    A->topRows<3>() *= inverse_scale_;
  }

 private:
  const KinematicModel& model_;
  const Eigen::Isometry3d T_a_;
  const bool position_only_;
  const double inverse_scale_;
  mutable Eigen::VectorXd q_;  // the joints of the last evaluation, and their Jacobian
  mutable Matrix6Xd J_;
};

}  // namespace

JacobianCompensator::JacobianCompensator() : JacobianCompensator(Options()) {}

const OptionTable<JacobianCompensator::Options>& JacobianCompensator::Options::Table() {
  static const OptionTable<Options> table = OptionTable<Options>("jacobian")
                                                .Add("length_scale", OptionUnit::kLength, &Options::length_scale,
                                                     "position rows are divided by it", Positive())
                                                .Include(GaussNewtonOptions::Table(), &Options::iteration);
  return table;
}

bool JacobianCompensator::Options::IsValid(std::string* why) const { return Table().Validate(*this, why); }

JacobianCompensator::Options JacobianCompensator::Options::FromYaml(const YAML::Node& node) {
  return Table().Read(node);
}

void JacobianCompensator::DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& /*seed*/,
                                       CompensationResult* result) const {
  const TwistResidual residual(identified().model(), target, options_.length_scale);
  RunGaussNewton(residual, options_.iteration, result);
}

}  // namespace kincal
