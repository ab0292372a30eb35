#pragma once
// The classic compensation: Newton's method on the 6-D pose error with the geometric Jacobian.
//
//   e(q) = (p_a - p_c(q), log(R_a R_c(q)^T))        position, and the rotation's logarithm (axis * angle),
//                                                   both in the measurement frame (PoseError)
//   J(q) = KinematicModel::JointJacobian(q)          rows: velocity of the tool point, angular velocity
//   dq   = (J^T W J + mu I)^-1 J^T W e              W = diag(1/L^2 (x3), 1 (x3)), L = length_scale
//
// with mu = 0 wherever the step is short, and near singular configurations (sigma_min / sigma_max of the
// weighted Jacobian below `singular_ratio`) the smallest mu that keeps |dq| within the trust radius
// (gauss_newton.h): the damping grows only where sigma_min is small and the error points along it.
// Since R(q + dq) = exp([J_w dq]x) R(q) to first order, this is Gauss-Newton on e; near the solution the
// error contracts quadratically. Position-only targets use the three position rows and the
// minimum-norm step.
//
// Compared with the seed's 12 equations (analytic_derivative): the same Jacobian information (the
// rotation part of the seed's A is [omega_i]x R, i.e. sqrt(2) |omega_i| in Frobenius norm), but 6
// equations instead of 12 and an error whose rotation part is the exact angle rather than a chord.
#include "compensators/common/gauss_newton.h"
#include "compensators/compensator.h"

namespace kincal {

class JacobianCompensator final : public Compensator {
 public:
  struct Options {
    // m per rad: position rows are divided by it, so a 1 mm error weighs like a rotation of
    // 1 mm / length_scale (0.5 m: 1 mm ~ 0.11 deg).
    double length_scale = 0.5;
    GaussNewtonOptions iteration;

    // Every key, its default, doc and requirement (framework/options.h).
    static const OptionTable<Options>& Table();
    bool IsValid(std::string* why) const;
    static Options FromYaml(const YAML::Node& node);
  };

  JacobianCompensator();
  explicit JacobianCompensator(const Options& options) : options_(options) {}
  std::string name() const override { return "jacobian"; }
  const Options& options() const { return options_; }

 protected:
  const BranchRestartOptions* branch_restarts() const override { return &options_.iteration.restarts; }

 private:
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override;
  Options options_;
};

}  // namespace kincal
