#pragma once
// The geometric estimator writes modified DH (the frames it builds are Craig's). A standard-DH robot is
// converted exactly first: regrouping the DH product
//   Rz(theta_1 + q_1) Dz(d_1) | Dx(a_1) Rx(alpha_1) Rz(theta_2 + q_2) Dz(d_2) | ... | Dx(a_n) Rx(alpha_n)
// (Rz and Dz about the same axis commute) gives MDH rows (alpha_{i-1}, a_{i-1}, theta_i, d_i) with
// alpha_0 = a_0 = 0, the same base, and the last Dx(a_n) Rx(alpha_n) folded into the tool. Joint angles
// keep their meaning, so drives, limits and markers carry over unchanged.
#include "robot/robot.h"

namespace kincal::geometric {

// An MDH robot with the same forward kinematics: a copy for "mdh", the conversion above for "dh".
// Throws std::invalid_argument for any other convention, naming it.
Robot ToMdhRobot(const Robot& robot, const std::string& who);

}  // namespace kincal::geometric
