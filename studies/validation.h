#pragma once
// Validation targets of a study and the ISO 9283 pose characteristics.
//
// A target is what a user asks the arm for: a tool pose in the measurement frame, together with the
// joints the controller's nominal inverse kinematics gives for it (the compensator's seed). Random targets
// are drawn as commanded joint angles within limits and mapped through the nominal robot, so the seed is
// exact and every method is scored on the same poses.
//
// ISO 9283:1998 (Manipulating industrial robots - Performance criteria and related test methods):
// - Section 6.2: the test cube sits in the part of the workspace used most; measurements are made on
//   the diagonal plane through two opposite edges of the cube. P1 is the centre of the cube; P2..P5 lie on
//   the plane's diagonals at 10 % of the diagonal's length from the corners, i.e.
//   P_i = C + 0.8 (corner_i - C). The tool keeps one orientation at every pose.
// - Section 7.2.1, pose accuracy over n cycles at a commanded pose c:
//     AP_P = sqrt((x_mean - x_c)^2 + (y_mean - y_c)^2 + (z_mean - z_c)^2)
//     AP_a = a_mean - a_c, AP_b = b_mean - b_c, AP_c = c_mean - c_c  (rotations about x, y, z)
// - Section 7.2.2, pose repeatability:
//     RP_l = l_mean + 3 S_l,  l_j = |p_j - p_mean|,  S_l = sqrt(sum (l_j - l_mean)^2 / (n - 1))
//     RP_a = 3 S_a (and b, c),  S_a = sqrt(sum (a_j - a_mean)^2 / (n - 1))
// Orientation deviations here are the components of the small rotation vector log(R_j R_c^T) in the
// measurement frame. The simulated arm has no backlash or dynamics, so the standard's cycle order
// P1 -> P5 -> P4 -> P3 -> P2 does not change the numbers; repeatability comes from joint noise.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "robot/robot.h"
#include "studies/study.h"

namespace kincal {

struct ValidationTarget {
  Eigen::Isometry3d T_meas_tool = Eigen::Isometry3d::Identity();
  Eigen::VectorXd q_nominal;  // the controller's nominal joint solution (commanded angles)
};

// `count` targets, commanded joints uniform within `limits` (rad; empty = the robot's limits).
std::vector<ValidationTarget> RandomTargets(const Robot& nominal, int count,
                                            const std::vector<std::pair<double, double>>& limits, uint64_t seed);
// `count` targets the real arm reaches: `truth`'s poses at joints uniform within `limits`, each with the
// controller's nominal solution for it (robot/nominal_ik.h, the branch next to those joints). Poses
// the nominal arm does not reach inside its limits are drawn again (the controller rejects them). Why not
// nominal poses: next to a fold of the nominal workspace (a boundary singularity) a nominal pose can lie
// outside the real arm's workspace on that branch (about 2 % of the seed arm's random configurations),
// and no compensator can reach it.
std::vector<ValidationTarget> ReachableRandomTargets(const Robot& nominal, const Robot& truth, int count,
                                                     const std::vector<std::pair<double, double>>& limits,
                                                     bool orientation, uint64_t seed);

// P1..P5 of a cube of edge `side` centred at `center`, axes along the measurement frame.
std::array<Eigen::Vector3d, 5> Iso9283Points(const Eigen::Vector3d& center, double side);

struct Iso9283Cube {
  Eigen::VectorXd center_configuration;  // rad, the pose the cube is built around
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double side = 0.0;
  std::vector<ValidationTarget> poses;  // P1..P5, constant tool orientation
};

// Places the cube: at spec.center_configuration, or (when empty) at the most dexterous configuration of a
// deterministic sample (largest smallest singular value of the joint Jacobian) at which the nominal
// inverse kinematics reaches all five poses on the same branch within the joint limits.
// Throws std::invalid_argument when no placement fits.
Iso9283Cube PlaceIso9283Cube(const Robot& nominal, const Iso9283Spec& spec, bool orientation, uint64_t seed);

struct Iso9283PoseStats {
  int cycles = 0;
  double ap_p = 0.0;                                 // m
  Eigen::Vector3d ap_abc = Eigen::Vector3d::Zero();  // rad
  double rp_l = 0.0;                                 // m
  Eigen::Vector3d rp_abc = Eigen::Vector3d::Zero();  // rad
};

// Pose accuracy and repeatability of attained poses (one per cycle, at least 2) at commanded pose `c`.
Iso9283PoseStats ComputeIso9283(const Eigen::Isometry3d& commanded, const std::vector<Eigen::Isometry3d>& attained);

}  // namespace kincal
