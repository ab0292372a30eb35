// Pose constraints of a measurement plan (planning/constraints.h).
#include "planning/constraints.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "framework/units.h"

namespace kincal {
namespace {

std::string Deg(double rad) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g deg", rad / kDegree);
  return buffer;
}

std::string Mm(double m) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g mm", m * 1e3);
  return buffer;
}

// Distance from the point p to the segment [a, b].
double PointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

}  // namespace

double SegmentDistance(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1, const Eigen::Vector3d& p2,
                       const Eigen::Vector3d& q2) {
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double eps = 1e-18;
  if (a <= eps && e <= eps) return r.norm();
  if (a <= eps) return PointSegmentDistance(p1, p2, q2);
  if (e <= eps) return PointSegmentDistance(p2, p1, q1);
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  double s = denom > eps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return ((p1 + s * d1) - (p2 + t * d2)).norm();
}

PoseConstraints::PoseConstraints(const Robot& robot, const PlanOptions& options) : robot_(robot), options_(options) {
  const int n = robot.dof();
  const std::vector<Eigen::Isometry3d> frames = robot.model().FramePoses(Eigen::VectorXd::Zero(n));
  std::vector<double> lengths;
  double longest = 0.0, reach = 0.0;
  for (int i = 0; i < n; ++i) {
    lengths.push_back((frames[i + 1].translation() - frames[i].translation()).norm());
    longest = std::max(longest, lengths.back());
    reach += lengths.back();
  }
  marker_tool_ = robot.MarkerPosition("");
  lengths.push_back((frames[n].inverse() * frames[n + 1] * marker_tool_).norm());
  reach += lengths.back();
  if (options.link_radii_m.empty()) {
    const double link = std::max(0.025, 0.1 * longest);
    radii_.assign(n, link);
    radii_.push_back(0.5 * link);
  } else if (static_cast<int>(options.link_radii_m.size()) != n + 1) {
    throw std::invalid_argument("link_radii_m: " + std::to_string(options.link_radii_m.size()) +
                                " radii for a robot of " + std::to_string(n) + " links and a tool (" +
                                std::to_string(n + 1) + ")");
  } else {
    radii_ = options.link_radii_m;
  }
  // Capsules joined through links shorter than their radii and the clearance touch at the joint by
  // construction: their clearance says nothing.
  for (int i = 0; i <= n; ++i) {
    double between = 0.0;
    for (int j = i + 1; j <= n; ++j) {
      if (j > i + 1 && between >= radii_[i] + radii_[j] + options.link_clearance) pairs_.emplace_back(i, j);
      between += lengths[j];
    }
  }
  const Eigen::Isometry3d base_inverse = robot.model().base().inverse();
  if (options.tracker_position_m.size() == 3) {
    tracker_ = Eigen::Vector3d(options.tracker_position_m[0], options.tracker_position_m[1],
                               options.tracker_position_m[2]);
  } else {
    tracker_ = Eigen::Vector3d(2.0 * reach, 0.0, (base_inverse * frames[1]).translation().z());
  }
}

std::vector<Capsule> PoseConstraints::Capsules(const Eigen::VectorXd& q) const {
  const int n = robot_.dof();
  const std::vector<Eigen::Isometry3d> frames = robot_.model().FramePoses(q);
  const Eigen::Isometry3d base_inverse = robot_.model().base().inverse();
  std::vector<Capsule> out;
  for (int i = 0; i < n; ++i) {
    out.push_back({base_inverse * frames[i].translation(), base_inverse * frames[i + 1].translation(), radii_[i]});
  }
  out.push_back({base_inverse * frames[n].translation(), base_inverse * (frames[n + 1] * marker_tool_), radii_[n]});
  return out;
}

void PoseConstraints::Marker(const Eigen::VectorXd& q, Eigen::Vector3d* position, Eigen::Vector3d* axis) const {
  const Eigen::Isometry3d T = robot_.model().base().inverse() * robot_.model().ForwardKinematics(q);
  *position = T * marker_tool_;
  const Eigen::Vector3d a(options_.reflector_axis[0], options_.reflector_axis[1], options_.reflector_axis[2]);
  *axis = (T.linear() * a).normalized();
}

std::string PoseConstraints::JointViolation(const Eigen::VectorXd& q) const {
  for (int j = 0; j < robot_.dof(); ++j) {
    const auto [lo, hi] = robot_.Limit(j);
    const double margin = robot_.model().joint_type(j) == JointType::kRevolute ? options_.joint_limit_margin : 0.0;
    if (!(q[j] >= lo + margin && q[j] <= hi - margin)) {
      return "joint limits: joint " + std::to_string(j + 1) + " within " + Deg(options_.joint_limit_margin) + " of its limits";
    }
  }
  return "";
}

std::string PoseConstraints::TrackerViolation(const Eigen::VectorXd& q, const std::vector<Capsule>& capsules) const {
  Eigen::Vector3d marker, axis;
  Marker(q, &marker, &axis);
  const Eigen::Vector3d sight = tracker_ - marker;
  const double range = sight.norm();
  if (range < options_.tracker_min_range || range > options_.tracker_max_range) {
    return "tracker range: the marker " + Mm(range) + " from the tracker, outside its range";
  }
  const double angle = std::acos(std::clamp(sight.dot(axis) / range, -1.0, 1.0));
  if (angle > options_.acceptance_angle) {
    return "acceptance angle: the tracker " + Deg(angle) + " off the reflector's axis (acceptance " + Deg(options_.acceptance_angle) +
           ")";
  }
  // The last link's and the tool's capsules hold the marker (the acceptance angle keeps the line of
  // sight off them); the others must leave it clear.
  for (size_t i = 0; i + 2 < capsules.size(); ++i) {
    const Capsule& c = capsules[i];
    if (SegmentDistance(marker, tracker_, c.a, c.b) < c.radius + options_.sight_clearance) {
      return "line of sight: link " + std::to_string(i + 1) + " in the way";
    }
  }
  return "";
}

std::string PoseConstraints::Violation(const Eigen::VectorXd& q) const {
  const std::string why = ArmViolation(q);
  return why.empty() && options_.tracker ? TrackerViolation(q, Capsules(q)) : why;
}

std::string PoseConstraints::ArmViolation(const Eigen::VectorXd& q) const {
  std::string why = JointViolation(q);
  if (!why.empty()) return why;
  const std::vector<Capsule> capsules = Capsules(q);
  const int n = robot_.dof();
  for (const auto& [i, j] : pairs_) {
    const double d = SegmentDistance(capsules[i].a, capsules[i].b, capsules[j].a, capsules[j].b);
    if (d < capsules[i].radius + capsules[j].radius + options_.link_clearance) {
      return "link clearance: " + (j == n ? std::string("the tool") : "link " + std::to_string(j + 1)) + " within " +
             Mm(d - capsules[i].radius - capsules[j].radius) + " of link " + std::to_string(i + 1);
    }
  }
  for (size_t i = 1; i < capsules.size(); ++i) {
    const double low = std::min(capsules[i].a.z(), capsules[i].b.z()) - capsules[i].radius;
    if (low < options_.floor_height + options_.floor_clearance) {
      return "floor: " + (static_cast<int>(i) == n ? std::string("the tool") : "link " + std::to_string(i + 1)) + " " +
             Mm(low - options_.floor_height) + " above the floor";
    }
  }
  return "";
}

}  // namespace kincal
