#pragma once
// Inverse kinematics of a robot as its controller solves it: every branch in closed form where the
// geometry allows, a numeric solver with restarts for the rest, and the branch a controller would take.
//
// The geometry is read from the model itself, never from its name: the joint screws at q = 0 (axis
// direction and a point on it, from the joint Jacobian) give the product of exponentials
//     T_meas_tool(q) = E_1(q_1) ... E_n(q_n) T_meas_tool(0)        (Brockett 1984; Murray, Li, Sastry 3.2)
// which is checked against the model's forward kinematics before it is used. Two closed forms of
// 6-joint revolute arms are detected:
//  - Pieper: three consecutive axes meet in one point w (a spherical wrist: IRB 120, Puma 560; or axes
//    3, 4, 5 of the seed's arm). The joints of the triple fix w, so the other three joints move w to a
//    known point: a 3R positioning problem solved through Pieper's invariants (distance to and height
//    along the outer axis), which leave one trigonometric polynomial of degree <= 4 in the inner joint
//    (roots from a companion matrix, <= 4 real solutions); the triple then is a rotation about w, solved
//    with Paden-Kahan subproblems 2 and 1 (2 solutions). Up to 8 branches.
//  - Three parallel axes (the UR family): with the two axes on one side meeting in a point, the height
//    along the common direction gives the lone joint (2 solutions), the fixed common direction the pair
//    (subproblem 2, 2 solutions), and the planar triple an elbow (circle intersection, 2). Up to 8.
// Every closed-form branch is polished by Newton steps on the model (so the result is exact to rounding
// even where the screws were read with rounding error), and every revolute joint is moved by multiples
// of 2 pi into its limits, to the representative closest to the reference.
//
// Singular poses are solved in closed form too. Where the solutions form a continuum (two axes of the
// wrist in line, so that only the sum of their angles matters; the 3R positioning problem's polynomial
// vanishing identically; a point on an axis, which frees that axis), the free joint takes the
// reference's value, as a controller holds it, and the rest is solved exactly by the same subproblems;
// if that member of the family leaves the joint limits, the free joint moves as little as the limits
// require. With three parallel axes a singular wrist also moves the elbow's target point, so the free
// angle is the one closest to the reference that the elbow reaches (possibly the only one, with the
// elbow stretched). Double roots of the 3R polynomial (two branches meeting) are refined to full
// precision, and joints on a limit to within 1e-9 rad are clamped onto it: every reachable pose inside
// the limits is `solved` or `singular` to 1e-9 m and 1e-9 rad, also at joints on multiples of 45 deg.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/options.h"
#include "robot/inverse_kinematics.h"
#include "robot/robot.h"

namespace kincal {

enum class IkStatus {
  kSolved,       // the pose is reached within tolerance, inside the joint limits
  kOutOfLimits,  // reached, but only outside the joint limits (q is the nearest such solution)
  kUnreachable,  // neither the closed form nor any start of the numeric solver reaches it; q is the best
                 // found (least pose error), whatever its singular values
  kSingular,     // reached inside the limits at a configuration where the Jacobian loses rank
                 // (sigma_min / sigma_max < singular_ratio); its solutions may form a continuum
};
std::string ToString(IkStatus status);

struct IkSolution {
  Eigen::VectorXd q;  // actual joint angles, rad (m for prismatic)
  IkStatus status = IkStatus::kUnreachable;
  double position_error = NAN;     // m
  double orientation_error = NAN;  // rad
  int branch = -1;                 // index in the closed form's enumeration; -1 for the numeric solver
  bool closed_form = false;
};

struct NominalIkOptions {
  double position_tolerance = 1e-9;     // m: a pose closer than this is reached
  double orientation_tolerance = 1e-9;  // rad
  // Geometry detection: axes within this distance (m) of a common point meet; directions whose cross
  // product is below `direction_tolerance` are parallel.
  double distance_tolerance = 1e-9;
  double direction_tolerance = 1e-9;
  // sigma_min / sigma_max of the Jacobian (rotation rows scaled by 1 m) below this is singular.
  double singular_ratio = 1e-6;
  // A named configuration, as signs of the joint angles wrapped to (-pi, pi]: one entry per joint,
  // +1 / -1 / 0 (either); e.g. {0, 0, +1, 0, -1, 0} for "elbow: q3 > 0, wrist flip: q5 < 0". Branches
  // that match are preferred (after the joint limits); empty: no preference. Among the preferred, the
  // branch closest to the reference (the previous target's solution, else the middle of the limits).
  std::vector<int> configuration;
  bool use_closed_form = true;       // false: always numeric (for tests and comparisons)
  InverseKinematicsOptions numeric;  // the fallback, also for position-only targets (a map in files)
  // Reading (`kincal ik --options`), IsValid and the documentation (`kincal methods --options ik`).
  static const OptionTable<NominalIkOptions>& Table();
  bool IsValid(std::string* why) const;
};

class NominalInverseKinematics {
 public:
  // Reads the geometry of `robot` once. Throws std::invalid_argument for invalid options.
  explicit NominalInverseKinematics(const Robot& robot, const NominalIkOptions& options = {});
  ~NominalInverseKinematics();
  NominalInverseKinematics(const NominalInverseKinematics&) = delete;
  NominalInverseKinematics& operator=(const NominalInverseKinematics&) = delete;

  // "pieper(4,5,6)", "parallel(2,3,4)" (1-based joints) or "numeric".
  std::string method() const;
  bool has_closed_form() const;

  // The solution a controller takes: closed form (every branch, the one closest to `reference`, or the
  // named branch; a free joint of a singular pose at the reference's value), else numeric from
  // `reference`. reference: the previous target's joints, or empty (the middle of the limits). Never
  // returns a non-finite q.
  IkSolution Solve(const Eigen::Isometry3d& T_meas_tool, const Eigen::VectorXd& reference) const;
  // Position-only target: numeric, from the reference.
  IkSolution SolvePosition(const Eigen::Vector3d& p_meas_tool, const Eigen::VectorXd& reference) const;
  // Every distinct closed-form branch that reaches the pose (inside the limits or not), sorted by
  // branch index; empty without a closed form or when none reaches it. At a singular pose, the member
  // of each continuous family with its free joint at the reference's value.
  std::vector<IkSolution> AllBranches(const Eigen::Isometry3d& T_meas_tool, const Eigen::VectorXd& reference) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace kincal
