#include "models/hayati_model.h"

#include <string>

namespace kincal {

HayatiModel::HayatiModel(std::vector<JointType> joint_types) {
  using K = ParameterInfo::Kind;
  using G = ParameterInfo::Group;
  const int dof = static_cast<int>(joint_types.size());
  std::vector<ParameterInfo> info;
  std::vector<Op> ops;
  for (int i = 0; i < dof; ++i) {
    const std::string s = "_" + std::to_string(i + 1);
    const int first = 5 * i;  // alpha, a, beta, theta, d
    info.push_back({"alpha" + s, "alpha", K::kAngle, G::kJoint, i + 1});
    info.push_back({"a" + s, "a", K::kLength, G::kJoint, i + 1});
    info.push_back({"beta" + s, "beta", K::kAngle, G::kJoint, i + 1});
    info.push_back({"theta" + s, "theta", K::kAngle, G::kJoint, i + 1});
    info.push_back({"d" + s, "d", K::kLength, G::kJoint, i + 1});
    const bool revolute = joint_types[i] == JointType::kRevolute;
    const int link = i + 1;
    ops.push_back({Op::kTx, first + 1, -1, link});
    ops.push_back({Op::kRx, first + 0, -1, link});
    ops.push_back({Op::kRy, first + 2, -1, link});
    ops.push_back({Op::kTz, first + 4, revolute ? -1 : i, link});
    ops.push_back({Op::kRz, first + 3, revolute ? i : -1, link});
  }
  BuildChain(std::move(joint_types), std::move(info), std::move(ops));
}

}  // namespace kincal
