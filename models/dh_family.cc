#include "models/dh_family.h"

#include <string>

namespace kincal {

std::vector<ParameterInfo> DhFamilyParameters(int dof) {
  using K = ParameterInfo::Kind;
  using G = ParameterInfo::Group;
  std::vector<ParameterInfo> info;
  for (int i = 1; i <= dof; ++i) {
    const std::string s = "_" + std::to_string(i);
    info.push_back({"alpha" + s, "alpha", K::kAngle, G::kJoint, i});
    info.push_back({"a" + s, "a", K::kLength, G::kJoint, i});
    info.push_back({"theta" + s, "theta", K::kAngle, G::kJoint, i});
    info.push_back({"d" + s, "d", K::kLength, G::kJoint, i});
  }
  return info;
}

}  // namespace kincal
