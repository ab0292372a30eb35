#pragma once
// Modified Denavit-Hartenberg (Craig 1989; the seed's Table 1, METHOD.md section 1).
// Row i (1-based) holds alpha_i and a_i, measured about/along x_{i-1} (Craig's alpha_{i-1}, a_{i-1}),
// the joint offset theta_i and d_i:
//     T_{i-1}^{i}(q_i) = Dx(a_i) * Rx(alpha_i) * Dz(d_i) * Rz(theta_i + q_i)
// (for a prismatic joint, Dz(d_i + q_i) and Rz(theta_i)). Compare KDL Frame::DH_Craig1989.
#include "models/chain_model.h"

namespace kincal {

class MdhModel final : public ChainModel {
 public:
  explicit MdhModel(std::vector<JointType> joint_types);
  explicit MdhModel(int revolute_joints) : MdhModel(std::vector<JointType>(revolute_joints, JointType::kRevolute)) {}
  std::unique_ptr<KinematicModel> Clone() const override { return std::make_unique<MdhModel>(*this); }
  std::string convention() const override { return "mdh"; }
  int JointAxisFrame(int joint) const override { return joint + 1; }
  std::vector<std::string> RowKeys() const override { return {"alpha", "a", "theta", "d"}; }
};

}  // namespace kincal
