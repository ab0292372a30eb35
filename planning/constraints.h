#pragma once
// What a measurement pose must meet (planning/plan_options.h gives the numbers): the joints a margin
// inside their limits; the arm's links, approximated as capsules (a segment and a radius: frame i-1 to
// frame i of the model, i = 1..n, then the flange to the marker), apart from each other and above the
// floor; and, with a tracker, the marker within its range, the line of sight within the reflector's
// acceptance angle and clear of every link's capsule but the last link's and the tool's, which hold the
// marker. All in the robot's base frame, SI.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/plan_options.h"
#include "robot/robot.h"

namespace kincal {

struct Capsule {
  Eigen::Vector3d a, b;  // the segment's ends, base frame, m
  double radius = 0.0;   // m
};

// Shortest distance between the segments [a0, a1] and [b0, b1] (Ericson, Real-Time Collision Detection,
// 5.1.9), m.
double SegmentDistance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                       const Eigen::Vector3d& b1);

class PoseConstraints {
 public:
  // Throws std::invalid_argument when the options do not fit the robot (link_radii_m's count).
  PoseConstraints(const Robot& robot, const PlanOptions& options);

  // The capsules of configuration q (actual joint angles, rad): n links then the tool.
  std::vector<Capsule> Capsules(const Eigen::VectorXd& q) const;
  // The marker's position and the reflector's axis (unit) at q, base frame.
  void Marker(const Eigen::VectorXd& q, Eigen::Vector3d* position, Eigen::Vector3d* axis) const;
  // "" when q meets every constraint, else the first one it breaks as "kind: detail", the kinds being
  // joint limits, link clearance, floor, tracker range, acceptance angle, line of sight.
  std::string Violation(const Eigen::VectorXd& q) const;
  // The same for the arm's own constraints only (joint limits, link clearance, floor): where it can work.
  std::string ArmViolation(const Eigen::VectorXd& q) const;

  const Eigen::Vector3d& tracker_position() const { return tracker_; }
  const std::vector<double>& radii() const { return radii_; }
  // Pairs of capsules (i < j) whose clearance is checked: not joined through links shorter than their
  // radii and the clearance together.
  const std::vector<std::pair<int, int>>& checked_pairs() const { return pairs_; }

 private:
  std::string JointViolation(const Eigen::VectorXd& q) const;
  std::string TrackerViolation(const Eigen::VectorXd& q, const std::vector<Capsule>& capsules) const;

  Robot robot_;
  PlanOptions options_;
  std::vector<double> radii_;
  std::vector<std::pair<int, int>> pairs_;
  Eigen::Vector3d tracker_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d marker_tool_ = Eigen::Vector3d::Zero();  // in the tool frame
};

}  // namespace kincal
