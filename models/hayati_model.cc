#include "models/hayati_model.h"

#include <cmath>
#include <stdexcept>
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

bool HayatiBetaIsRedundant(const KinematicModel& model, int joint) {
  if (model.convention() != "hayati") throw std::invalid_argument("HayatiBetaIsRedundant: not a hayati model");
  const std::string s = "_" + std::to_string(joint);
  // z_i in frame i-1 is Rx(alpha_i) Ry(beta_i) e_z, whose z component is cos(alpha_i) cos(beta_i).
  const double cos_angle = std::cos(model.Parameter("alpha" + s)) * std::cos(model.Parameter("beta" + s));
  return std::abs(cos_angle) < std::cos(kHayatiParallelAxes);
}

std::string HayatiModel::RedundantParameterReason(int index) const {
  const ParameterInfo& info = parameter_info()[index];
  if (info.group != ParameterInfo::Group::kJoint || info.key != "beta" || !HayatiBetaIsRedundant(*this, info.joint)) {
    return "";
  }
  if (info.joint == 1) return "Hayati's beta where axis 1 is not parallel to the base's z: redundant with the base";
  const std::string i = std::to_string(info.joint), before = std::to_string(info.joint - 1);
  return "Hayati's beta where axes " + before + " and " + i + " are not parallel: redundant with d_" + before +
         " and theta_" + before;
}

}  // namespace kincal
