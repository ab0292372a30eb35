#pragma once
// Universal Robots' kinematics YAML (ur_description's `kinematics_parameters_file`, ur_calibration's
// output) in and out.
//
// The file: a `kinematics:` map with the joints shoulder, upper_arm, forearm, wrist_1, wrist_2, wrist_3,
// each {x, y, z, roll, pitch, yaw} (m, rad), and a `hash` (the controller's calibration checksum, which
// the ROS driver compares with the robot's). ur_description builds the URDF joint
//     T_parent_child(q) = Trans(x, y, z) * Rz(yaw) Ry(pitch) Rx(roll) * Rz(q)
// from each, from base_link_inertia (the controller's base frame) to wrist_3_link, which coincides
// with tool0 (the two fixed joints between them cancel). That is kincal's urdf convention with every
// axis along z, no joint offset, and base and tool the identity: held exactly, digit for digit, so the
// robot file is in that convention.
//
// Export from any 6R robot: each joint frame at q = 0 (z on the joint's axis, from the robot converted to
// the urdf convention, its axis and zero offset folded into the frame) becomes the joint's origin in the
// previous one, starting from the robot's base frame. The forward kinematics from the base to the
// tool is then  base * [the file's chain](q) * tool', tool' = the robot's tool seen from the last joint
// frame. What the file cannot hold is listed: the base (the installation: T_meas_base), the tool (the
// controller's TCP), drives, coupling and joint errors (the controller reads its joints as they are).
#include <string>
#include <vector>

#include "robot/robot.h"

namespace kincal {

// True for a file ending in .yaml or .yml, or whose YAML top level has a `kinematics` key.
bool LooksLikeUrKinematics(const std::string& path);

// The robot (6 revolute joints, urdf convention, base and tool identity, ur_description's joint limits:
// +-2 pi, the elbow +-pi). Throws std::invalid_argument "file:line:column: what was expected".
Robot ReadUrKinematics(const std::string& path);
Robot ParseUrKinematics(const std::string& text, const std::string& source_name);

struct UrKinematicsExport {
  std::string text;                  // the file, with what it does not hold as comments at the top
  std::vector<std::string> dropped;  // one line per item not held
  // The robot as the file holds it, with the base and tool the robot had (set in the controller's
  // installation and TCP) and no drives, coupling or joint errors: what the controller will do.
  Robot held;
};

// Throws std::invalid_argument (one line) unless the robot has 6 revolute joints.
UrKinematicsExport ExportUrKinematics(const Robot& robot, const std::string& source_name);

}  // namespace kincal
