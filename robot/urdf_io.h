#pragma once
// URDF in and out (urdfdom, the ROS parser Debian ships; its TinyXML for editing).
//
// Import: the serial chain between two links of a URDF becomes a robot in the urdf convention
// (models/urdf_model.h): one row per moving joint (revolute, continuous, prismatic), whose origin is the
// product of the fixed joints since the previous moving joint and the joint's own origin; the fixed
// joints after the last moving joint are the tool; the base is the identity (the base link is the
// measurement frame). Limits and velocity limits come from the joints' <limit> elements (continuous
// joints: -pi..pi). The robot remembers the file, links and joints (Robot::urdf).
//
// Export: a robot with that provenance is written as the source file with only joint origins, limits
// and velocity limits edited, everything else (links, meshes, inertials, collision, names, comments, other
// joints) unchanged. Each moving joint's frame is the source's frame turned by the smallest rotation that
// takes the source axis onto the calibrated one and moved onto the calibrated axis line, so link
// geometry stays where it was and the axis numbers stay the same; the calibrated tool goes into the first
// fixed joint after the last moving joint. The base link is the robot's measurement frame, as on import
// (the pose from the base link is T_meas_tool(q), base included: a base identified against an
// instrument moves joint 1's origin). A robot without provenance is written as a new URDF:
// world (the measurement frame) -> base_link (fixed, the base), link_1 .. link_n, -> tool0 (fixed, the tool).
#include <string>

#include "robot/robot.h"

namespace kincal {

struct UrdfImportOptions {
  std::string base_link;            // required
  std::string tip_link;             // required
  std::string convention = "urdf";  // the robot's convention (converted exactly from the URDF chain)
};

// Throws std::invalid_argument with one line (file, and line and column for XML errors) when the file
// does not parse, the links are not joined by a serial chain, or a joint on it is floating or planar.
Robot ImportUrdf(const std::string& path, const UrdfImportOptions& options);

// The URDF text of `robot` (see above). Throws std::invalid_argument when the source URDF cannot be read
// or no longer has the chain, or the calibrated chain does not fit it (one line saying why).
std::string RobotToUrdf(const Robot& robot);

}  // namespace kincal
