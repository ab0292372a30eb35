#include "compensators/analytic_derivative/analytic_derivative_compensator.h"

#include <algorithm>
#include <cmath>

#include "framework/math.h"
#include "models/chain_model.h"

namespace kincal {
namespace {

// Delta_T = T_a - T_c (eq. 13) and its derivative, stacked as in METHOD.md 4 step 3.
class PoseMatrixResidual final : public PoseResidual {
 public:
  PoseMatrixResidual(const KinematicModel& model, const CompensationTarget& target, double length_scale)
      : model_(model),
        T_a_(target.T_meas_tool.matrix()),
        position_only_(!target.has_orientation),
        inverse_scale_(1.0 / length_scale) {}

  void Evaluate(const Eigen::VectorXd& q, Eigen::VectorXd* r, double* position_error,
                double* orientation_error) const override {
    // The Jacobian comes from the same pass; Linearize takes it (and the rotation) when asked at these
    // joints (after an accepted step, as the iteration does).
    T_ = PoseAndJointJacobian(model_, q, &J_);
    q_ = q;
    const Eigen::Matrix4d delta = T_a_ - T_.matrix();
    const Eigen::Vector3d dp = delta.block<3, 1>(0, 3);
    *position_error = dp.norm();
    if (position_only_) {
      *r = dp * inverse_scale_;
      *orientation_error = 0.0;
      return;
    }
    r->resize(12);
    Stack(delta, r->data());
    // |R_a - R_c|_F = 2 sqrt(2) sin(angle / 2), exactly.
    const double chord = delta.topLeftCorner<3, 3>().norm() / (2.0 * std::sqrt(2.0));
    *orientation_error = 2.0 * std::asin(std::min(chord, 1.0));
  }

  void Linearize(const Eigen::VectorXd& q, Eigen::MatrixXd* A) const override {
    if (!(q_.size() == q.size() && q_ == q)) {
      T_ = PoseAndJointJacobian(model_, q, &J_);
      q_ = q;
    }
    // Eq. 11 from the Jacobian: dT/dq_i = [omega_i x R, v_i] (ChainModel::PoseDerivatives).
    const int n = static_cast<int>(J_.cols());
    if (position_only_) {
      A->resize(3, n);
      for (int i = 0; i < n; ++i) A->col(i) = J_.col(i).head<3>() * inverse_scale_;
      return;
    }
    A->resize(12, n);
    Eigen::Matrix4d dT = Eigen::Matrix4d::Zero();
    for (int i = 0; i < n; ++i) {
      dT.topLeftCorner<3, 3>() = Skew(J_.col(i).tail<3>()) * T_.linear();
      dT.topRightCorner<3, 1>() = J_.col(i).head<3>();
      Stack(dT, A->col(i).data());
    }
  }

 private:
  // Rows 0-2 of a 4x4 matrix, column by column, position entries weighted (the constant 4th row dropped).
  void Stack(const Eigen::Matrix4d& M, double* out) const {
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < 3; ++row) out[3 * c + row] = M(row, c);
    }
    for (int row = 0; row < 3; ++row) out[9 + row] = M(row, 3) * inverse_scale_;
  }

  const KinematicModel& model_;
  const Eigen::Matrix4d T_a_;
  const bool position_only_;
  const double inverse_scale_;
  mutable Eigen::VectorXd q_;  // the joints of the last evaluation, their pose and Jacobian
  mutable Eigen::Isometry3d T_;
  mutable Matrix6Xd J_;
};

}  // namespace

const OptionTable<AnalyticDerivativeCompensator::Options>& AnalyticDerivativeCompensator::Options::Table() {
  static const OptionTable<Options> table =
      OptionTable<Options>("analytic_derivative")
          .Add("length_scale", OptionUnit::kLength, &Options::length_scale, "position entries are divided by it",
               Positive())
          .Add("plain", &Options::plain, "the paper's form verbatim: 1 m, pseudo-inverse steps, no damping")
          .Include(GaussNewtonOptions::Table(), &Options::iteration);
  return table;
}

bool AnalyticDerivativeCompensator::Options::IsValid(std::string* why) const { return Table().Validate(*this, why); }

AnalyticDerivativeCompensator::Options AnalyticDerivativeCompensator::Options::FromYaml(const YAML::Node& node) {
  return Table().Read(node);
}

AnalyticDerivativeCompensator::AnalyticDerivativeCompensator() : AnalyticDerivativeCompensator(Options()) {}

AnalyticDerivativeCompensator::AnalyticDerivativeCompensator(const Options& options) : options_(options) {
  if (options_.plain) {
    options_.length_scale = 1.0;
    options_.iteration.singular_ratio = 0.0;
    options_.iteration.max_step_halvings = 0;
  }
}

void AnalyticDerivativeCompensator::DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& /*seed*/,
                                                 CompensationResult* result) const {
  const PoseMatrixResidual residual(identified().model(), target, options_.length_scale);
  RunGaussNewton(residual, options_.iteration, result);
}

}  // namespace kincal
