#include "models/dh_model.h"

#include "models/dh_family.h"

namespace kincal {

DhModel::DhModel(std::vector<JointType> joint_types) {
  std::vector<Op> ops;
  for (int i = 0; i < static_cast<int>(joint_types.size()); ++i) {
    const bool revolute = joint_types[i] == JointType::kRevolute;
    const int link = i + 1;
    ops.push_back({Op::kRz, DhParameterIndex(i, kTheta), revolute ? i : -1, link});
    ops.push_back({Op::kTz, DhParameterIndex(i, kD), revolute ? -1 : i, link});
    ops.push_back({Op::kTx, DhParameterIndex(i, kA), -1, link});
    ops.push_back({Op::kRx, DhParameterIndex(i, kAlpha), -1, link});
  }
  const int dof = static_cast<int>(joint_types.size());
  BuildChain(std::move(joint_types), DhFamilyParameters(dof), std::move(ops));
}

}  // namespace kincal
