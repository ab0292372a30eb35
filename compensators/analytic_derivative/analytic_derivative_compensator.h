#pragma once
// The seed's compensation: the "improved differential method" on the pose matrix (Liu et al.; METHOD.md
// section 4, eqs. 11-14).
//
//   Delta_T = T_a - T_c(theta)                       (eq. 13; T_c by the identified model)
//   B       = the 12 entries of Delta_T's top three rows, stacked column by column
//             (rotation columns x, y, z: 9 unitless entries, then the 3 position entries)
//   A       = the same 12 entries of dT_c/dtheta_i in column i (eq. 11, KinematicModel::PoseDerivatives)
//   Delta_theta = A^+ B,  theta <- theta + Delta_theta, repeated from the controller's nominal solution.
//
// What the paper leaves open, and the choices made here:
// - Units. The 12 equations mix unitless rotation entries with lengths, so the unit of length decides
//   how position weighs against orientation. The position entries are divided by `length_scale`; since
//   |R_a - R_c|_F = 2 sqrt(2) sin(angle / 2), a rotation by a small angle phi weighs like a position
//   error of sqrt(2) * phi * length_scale. The reachable 6-D targets of a 6-joint arm are solved
//   exactly either way; the weight matters for the path, near singularities, and for targets that
//   cannot be met exactly.
// - `plain: true` is the paper's form verbatim: position entries in metres (SI) against the unitless
//   rotation entries, Delta_theta = A^+ B by a complete orthogonal decomposition, no damping, every
//   step taken.
// - Otherwise: damped least squares near singular configurations (singular values of the weighted A),
//   a step-halving line search on |B|, and a stop on tolerance and on iterations (gauss_newton.h).
// - Position-only targets use the 3 position equations (the 4th column of Delta_T); the step is then
//   the minimum-norm joint change.
#include "compensators/common/gauss_newton.h"
#include "compensators/compensator.h"

namespace kincal {

class AnalyticDerivativeCompensator final : public Compensator {
 public:
  struct Options {
    // m. Position entries of Delta_T are divided by it (see above). 0.5 m is about the seed arm's
    // reach, so a 1 mm position error weighs like a 0.08 deg rotation.
    double length_scale = 0.5;
    // The paper's form verbatim: length_scale = 1 m (SI), pseudo-inverse steps, no damping, no line
    // search. The tolerances and max_iterations still apply.
    bool plain = false;
    GaussNewtonOptions iteration;

    // Every key, its default, doc and requirement (framework/options.h).
    static const OptionTable<Options>& Table();
    bool IsValid(std::string* why) const;
    static Options FromYaml(const YAML::Node& node);
  };

  AnalyticDerivativeCompensator();
  explicit AnalyticDerivativeCompensator(const Options& options);
  std::string name() const override { return "analytic_derivative"; }
  const Options& options() const { return options_; }

 protected:
  const BranchRestartOptions* branch_restarts() const override { return &options_.iteration.restarts; }

 private:
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override;
  Options options_;
};

}  // namespace kincal
