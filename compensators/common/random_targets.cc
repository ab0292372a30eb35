#include "compensators/common/random_targets.h"

#include <stdexcept>

#include "framework/error.h"
#include "robot/inverse_kinematics.h"
#include "framework/random.h"
#include "framework/svd.h"

namespace kincal {

bool RandomTargetOptions::IsValid(std::string* why) const {
  const auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (count < 0) return fail("count must be >= 0");
  if (!(min_sigma_ratio >= 0 && min_sigma_ratio < 1)) return fail("min_sigma_ratio must be in [0, 1)");
  if (!(length_scale > 0)) return fail("length_scale must be > 0");
  if (!(max_seed_distance > 0)) return fail("max_seed_distance must be > 0");
  return true;
}

double SingularValueRatio(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  return s.size() > 0 && s[0] > 0 ? s[s.size() - 1] / s[0] : 0.0;
}

double JacobianConditionRatio(const KinematicModel& model, const Eigen::VectorXd& q, double length_scale) {
  Matrix6Xd J = model.JointJacobian(q);
  J.topRows<3>() /= length_scale;
  return SingularValueRatio(J);
}

RandomTargets MakeRandomTargets(const Robot& nominal, const Robot& identified, const RandomTargetOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("random targets: " + OneLine(why));
  if (nominal.dof() != identified.dof())
    throw std::invalid_argument("random targets: the robots differ in joint count");
  const int n = identified.dof();
  RandomTargets out;
  Rng rng(options.seed);
  InverseKinematicsOptions ik;
  ik.restarts = 0;  // the controller's solution next to the true configuration, or none
  while (static_cast<int>(out.targets.size()) < options.count) {
    if (out.rejected > 100 * (options.count + 10)) {
      throw std::invalid_argument("random targets: almost no configuration passes (nominal IK or min_sigma_ratio)");
    }
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = identified.Limit(j);
      q[j] = rng.Uniform(low, high);
    }
    if (options.min_sigma_ratio > 0 &&
        JacobianConditionRatio(identified.model(), q, options.length_scale) < options.min_sigma_ratio) {
      ++out.rejected;
      continue;
    }
    CompensationTarget target;
    target.T_meas_tool = identified.model().ForwardKinematics(q);
    target.has_orientation = options.orientation;
    const InverseKinematicsResult seed =
        SolveInverseKinematics(nominal, target.T_meas_tool, options.orientation, q, ik);
    bool within_limits = true;
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = nominal.Limit(j);
      within_limits = within_limits && seed.q[j] >= low && seed.q[j] <= high;
    }
    const bool same_branch = (seed.q - q).cwiseAbs().maxCoeff() <= options.max_seed_distance;
    if (!seed.converged || !within_limits || !same_branch) {
      ++out.rejected;
      continue;
    }
    target.seed = seed.q;
    out.targets.push_back(target);
    out.q_true.push_back(q);
  }
  return out;
}

}  // namespace kincal
