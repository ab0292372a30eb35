#pragma once
// Robot files (YAML), DESIGN.md "File contracts (v1)":
//
//   name: paper6
//   convention: mdh                 # mdh | dh | hayati | poe | urdf (models/model_factory.h)
//   units: {length: mm, angle: deg}
//   joints:                         # the convention's row keys (KinematicModel::RowKeys): mdh row i:
//     - {alpha: 0, a: 0, theta: 0, d: 0}          # alpha, a (about/along x_{i-1}), theta offset, d;
//                                   # hayati adds beta; poe: x, y, z, roll, pitch, yaw, theta; optional
//                                   # `type: prismatic`
//   drives: {ratio: [...], counts_per_rev: [...], encoder_zero: [...]}   # optional; encoder_zero optional
//   limits: [[min, max], ...]       # optional, angle unit; default +-90 deg
//   base: {xyz: [0, 0, 0], rpy: [0, 0, 0]}      # T_meas_base (default identity)
//   tool: {xyz: [0, 0, 0], rpy: [0, 0, 0]}      # T_n_tool (default identity)
//   markers: {SMR1: [x, y, z]}      # optional, marker positions in the tool frame
//   sessions: {2: {xyz: [...], rpy: [...]}}     # optional, T_meas_base of each session
//   velocity_limits, coupling, gravity, joint_errors   # optional joint-level terms (robot.h,
//                                                      # models/joint_errors.h)
//   urdf: {source, base, tip, joints}                 # optional, where an imported robot came from
//   fixtures: {pivots: {P1: {xyz: [...], sd: 1}}, planes: {table: {normal: [0, 0, 1], offset: 300}},
//              points: {socket: {xyz: [...]}}}        # optional (robot/fixtures.h); without sd: known
//
// Values are converted to SI on reading and back on writing; writing keeps every digit, so
// read -> write gives the same numbers and read -> write -> read the same bits.
#include <string>

#include "robot/robot.h"

namespace kincal {

// Throws std::invalid_argument "file:line:col: what" on any problem (unknown key, wrong type, ...).
Robot ReadRobotFile(const std::string& path);
Robot ParseRobotYaml(const std::string& text, const std::string& source_name);

std::string RobotToYaml(const Robot& robot);
// Writes atomically: the file is complete or untouched.
void WriteRobotFile(const Robot& robot, const std::string& path);

}  // namespace kincal
