#include "compensators/analytic_derivative/analytic_derivative_compensator.h"

#include <algorithm>
#include <cmath>

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
    const Eigen::Matrix4d delta = T_a_ - model_.ForwardKinematics(q).matrix();
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
    const std::vector<Eigen::Matrix4d> dT = model_.PoseDerivatives(q);  // eq. 11
    const int n = static_cast<int>(dT.size());
    if (position_only_) {
      A->resize(3, n);
      for (int i = 0; i < n; ++i) A->col(i) = dT[i].block<3, 1>(0, 3) * inverse_scale_;
      return;
    }
    A->resize(12, n);
    for (int i = 0; i < n; ++i) Stack(dT[i], A->col(i).data());
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
