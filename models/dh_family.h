#pragma once
// Parameter declarations shared by the DH family: four per joint, alpha_i, a_i, theta_i, d_i.
#include <vector>

#include "framework/kinematic_model.h"

namespace kincal {

// Parameter index of `key` ("alpha", "a", "theta", "d") of joint i (0-based) in a DH-family model.
inline int DhParameterIndex(int joint, int key) { return 4 * joint + key; }
enum DhKey { kAlpha = 0, kA = 1, kTheta = 2, kD = 3 };

std::vector<ParameterInfo> DhFamilyParameters(int dof);

}  // namespace kincal
