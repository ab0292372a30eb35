#pragma once
// Standard Denavit-Hartenberg (Denavit & Hartenberg 1955; Spong's form). Row i holds theta_i, d_i, a_i,
// alpha_i, all measured at joint i's own frame:
//     T_{i-1}^{i}(q_i) = Rz(theta_i + q_i) * Dz(d_i) * Dx(a_i) * Rx(alpha_i)
// (for a prismatic joint, Rz(theta_i) and Dz(d_i + q_i)). Compare KDL Frame::DH.
#include "models/chain_model.h"

namespace kincal {

class DhModel final : public ChainModel {
 public:
  explicit DhModel(std::vector<JointType> joint_types);
  explicit DhModel(int revolute_joints) : DhModel(std::vector<JointType>(revolute_joints, JointType::kRevolute)) {}
  std::unique_ptr<KinematicModel> Clone() const override { return std::make_unique<DhModel>(*this); }
  std::string convention() const override { return "dh"; }
  int JointAxisFrame(int joint) const override { return joint; }
  std::vector<std::string> RowKeys() const override { return {"alpha", "a", "theta", "d"}; }
};

}  // namespace kincal
