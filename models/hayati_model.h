#pragma once
// Modified DH extended with Hayati's rotation about y (Hayati & Mirmirani 1985; the remedy METHOD.md
// section 2 names for parallel axes). Row i holds alpha_i, a_i, beta_i, theta_i, d_i:
//     T_{i-1}^{i}(q_i) = Dx(a_i) * Rx(alpha_i) * Ry(beta_i) * Dz(d_i) * Rz(theta_i + q_i)
// With beta_i = 0 this is exactly MdhModel. When axes i-1 and i are (nearly) parallel, a small tilt of
// axis i about y is beta_i, a well-conditioned parameter, where MDH would need a huge d or offset; for
// such rows d_i and the previous row's d are then redundant, and the identifiability analysis of the
// estimators fixes one of them. For non-parallel rows beta_i is the redundant one (with d_{i-1} and
// theta_{i-1}, to first order), and the error-model estimators hold it (HayatiBetaIsRedundant): left
// free, it is exactly redundant without joint-level errors and only weakly separated through the gravity
// terms with them, which leaves a near-singular problem (standard deviations of hundreds of radians).
#include "models/chain_model.h"

namespace kincal {

// Row `joint` (1-based) of a Hayati model: true when beta_joint is redundant, i.e. axis joint-1 (the base
// frame's z for row 1) and axis joint are further than kHayatiParallelAxes from parallel or antiparallel
// at the model's current values. Throws std::invalid_argument for another convention.
inline constexpr double kHayatiParallelAxes = 10.0 * 3.14159265358979323846 / 180.0;  // rad
bool HayatiBetaIsRedundant(const KinematicModel& model, int joint);

class HayatiModel final : public ChainModel {
 public:
  explicit HayatiModel(std::vector<JointType> joint_types);
  explicit HayatiModel(int revolute_joints)
      : HayatiModel(std::vector<JointType>(revolute_joints, JointType::kRevolute)) {}
  std::unique_ptr<KinematicModel> Clone() const override { return std::make_unique<HayatiModel>(*this); }
  std::string convention() const override { return "hayati"; }
  int JointAxisFrame(int joint) const override { return joint + 1; }
  std::vector<std::string> RowKeys() const override { return {"alpha", "a", "beta", "theta", "d"}; }
  // beta_i where HayatiBetaIsRedundant: redundant with the base (row 1) or with d_{i-1} and theta_{i-1}.
  std::string RedundantParameterReason(int index) const override;
};

}  // namespace kincal
