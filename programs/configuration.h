#pragma once
// The configuration fields by which robot programs name the controller's branch of a Cartesian target,
// and the controller's inverse kinematics on the branch they name.
//
// ABB (RAPID reference manual, data type confdata; "Robot configuration" in its RAPID overview):
// cf1, cf4, cf6 are the quadrants of axes 1, 4 and 6, floor(angle / 90 deg) (0 for 0..90 deg, -1 for
// -90..0 deg, ...). cfx, for serial six-axis arms, numbers the 8 arm and wrist configurations:
//     cfx = 4 * (wrist centre behind axis 1) + 2 * (wrist centre behind the lower arm) + (axis 5 < 0)
// "Behind axis 1": the wrist centre's x in axis 1's frame (turning with axis 1) is negative, i.e. on the
// other side of the plane through axis 1 (across the arm) than at the zero position; "behind
// the lower arm": the wrist centre is on the other side of the line through axes 2 and 3 than at the
// zero position, where the arm stands with the wrist in front (cfx 0 at all-zero joints).
// KUKA (KSS system-integrator manual, "Status and Turn"; read as the manual's tables and the robot-forum
// threads on them describe it): status S, bit 0 = the wrist root point (axes 4, 5, 6 meet there) has a
// negative x in the A1 coordinate system (overhead area); bit 1 = the wrist root point is on the side of
// the straight line through A2 and A3 it is on at HOME (A2 = -90, A3 = +90 deg), where bit 1 is set
// (A3 >= phi); bit 2 = A5 < 0 (A5 in -180..0 deg). Turn T: bit i (0-based) = axis A(i+1) < 0 deg.
// Both are read from the model's joint axes (the Jacobian's columns), never from its name, so any
// KUKA-like or ABB-like 6R arm in any convention works as long as its joint angles are the controller's.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "programs/program.h"
#include "robot/nominal_ik.h"
#include "robot/robot.h"

namespace kincal {

// The rules of one convention for one controller (its zero and HOME sides read once).
class ConfigurationRules {
 public:
  // Throws std::invalid_argument for ABB and KUKA on a robot without 6 revolute joints.
  ConfigurationRules(ConfigurationConvention convention, const Robot& controller);
  ConfigurationConvention convention() const { return convention_; }
  // The configuration fields of the controller's joints q (rad): ABB {cf1, cf4, cf6, cfx}, KUKA {S, T},
  // none: empty.
  std::vector<int> Of(const Eigen::VectorXd& q) const;
  // The controller's solution of T_meas_tool on the branch `configuration` names: first its inverse
  // kinematics nearest `reference`, else every closed-form branch; each revolute joint moved by whole
  // turns within the limits to agree with the named fields, nearest `reference`. An empty
  // `configuration` (or kNone): the solution nearest `reference` (the joints the controller comes from).
  struct Solution {
    Eigen::VectorXd q;
    bool found = false;  // inside the limits, with exactly the named configuration
  };
  Solution Solve(const NominalInverseKinematics& ik, const Eigen::Isometry3d& T_meas_tool,
                 const std::vector<int>& configuration, const Eigen::VectorXd& reference) const;
  // q_in with each revolute joint moved by whole turns within the limits to agree with the named fields,
  // nearest `reference` (n values); true when *q then has exactly the named configuration.
  bool Fit(const Eigen::VectorXd& q_in, const std::vector<int>& configuration, const Eigen::VectorXd& reference,
           Eigen::VectorXd* q) const;

 private:
  ConfigurationConvention convention_;
  const Robot* controller_;
  // The criteria's signs where the manufacturers define them: the wrist centre in front of axis 1 at the
  // zero position (both); the lower-arm criterion at zero (ABB) and at HOME (KUKA).
  double zero_front_ = 1, zero_side_ = 1, home_side_ = 1;
};

}  // namespace kincal
