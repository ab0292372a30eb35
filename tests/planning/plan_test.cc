// The planning library (planning/): every planned pose meets the constraints, checked by an
// independent computation (standard DH written out here, distances by sampling along the segments),
// and every rejected candidate breaks one; segment distances against sampling; the greedy choice's
// rank-3 updates against the criteria computed directly; the order's 2-opt optimality; reproducible
// candidates.
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "framework/units.h"
#include "planning/constraints.h"
#include "planning/plan.h"
#include "planning/tour.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

Robot Ur10() {
  Robot robot = LoadExampleRobot("ur10_joint_errors.yaml");
  robot.joint_errors = JointErrors();
  return robot;
}

// Sampled distance between two segments: >= the exact one, and above it by at most half the longer
// segment's length over n.
double SampledDistance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                       const Eigen::Vector3d& b1, int n = 200) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector3d p = a0 + (a1 - a0) * (static_cast<double>(i) / n);
    for (int j = 0; j <= n; ++j) best = std::min(best, (p - (b0 + (b1 - b0) * (static_cast<double>(j) / n))).norm());
  }
  return best;
}

// Frame origins 0..6 and the marker (the tool origin) of a standard-DH arm in its base frame, from the
// robot file's parameters: T_i = Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i).
std::vector<Eigen::Vector3d> DhPoints(const Robot& robot, const Eigen::VectorXd& q, Eigen::Matrix3d* R_tool) {
  const KinematicModel& m = robot.model();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> points = {T.translation()};
  for (int i = 1; i <= 6; ++i) {
    const std::string k = std::to_string(i);
    T = T * Eigen::AngleAxisd(m.Parameter("theta_" + k) + q[i - 1], Eigen::Vector3d::UnitZ()) *
        Eigen::Translation3d(m.Parameter("a_" + k), 0, m.Parameter("d_" + k)) *
        Eigen::AngleAxisd(m.Parameter("alpha_" + k), Eigen::Vector3d::UnitX());
    points.push_back(T.translation());
  }
  T = T * m.tool();
  points.push_back(T.translation());
  *R_tool = T.linear();
  return points;
}

// The constraints of `options` at q, computed again: "" or what is broken. Distances are sampled with n
// steps per segment; `margin` is added to every required distance: 0 checks a pose that must meet them
// (a sampled distance is never below the exact one), a sampling step one that must break one.
std::string IndependentViolation(const Robot& robot, const Eigen::VectorXd& q, const PlanOptions& o,
                                 const Eigen::Vector3d& tracker, double margin, int n) {
  for (int j = 0; j < 6; ++j) {
    if (q[j] < robot.Limit(j).first + o.joint_limit_margin || q[j] > robot.Limit(j).second - o.joint_limit_margin)
      return "joint limits";
  }
  Eigen::Matrix3d R;
  const std::vector<Eigen::Vector3d> p = DhPoints(robot, q, &R);
  const double r = std::max(0.025, 0.1 * 0.612);  // UR10: the longest link is a_2 = 0.612 m
  const std::vector<double> radius = {r, r, r, r, r, r, 0.5 * r};
  const std::vector<double> length = {0.1273, 0.612, 0.5723, 0.163941, 0.1157, 0.0922, (p[7] - p[6]).norm()};
  for (int i = 0; i < 7; ++i) {
    for (int j = i + 2; j < 7; ++j) {
      double between = 0;
      for (int k = i + 1; k < j; ++k) between += length[k];
      if (between < radius[i] + radius[j] + o.link_clearance) continue;
      if (SampledDistance(p[i], p[i + 1], p[j], p[j + 1], n) < radius[i] + radius[j] + o.link_clearance + margin)
        return "link clearance";
    }
  }
  for (int i = 1; i < 7; ++i) {
    if (std::min(p[i].z(), p[i + 1].z()) - radius[i] < o.floor_height + o.floor_clearance + margin) return "floor";
  }
  const Eigen::Vector3d sight = tracker - p[7];
  if (sight.norm() < o.tracker_min_range || sight.norm() > o.tracker_max_range) return "tracker range";
  if (std::acos(sight.normalized().dot(R.col(2))) > o.acceptance_angle) return "acceptance angle";
  for (int i = 0; i < 5; ++i) {  // links 1..5: link 6 and the tool hold the marker
    if (SampledDistance(p[7], tracker, p[i], p[i + 1], n) < radius[i] + o.sight_clearance + margin)
      return "line of sight";
  }
  return "";
}

TEST(PlanConstraints, PlannedPosesMeetThemAndRejectedOnesBreakThem) {
  const Robot robot = Ur10();
  PlanOptions options;
  options.generated_candidates = 4000;
  const CandidatePool pool = GenerateCandidates(robot, options);
  const MeasurementPlan plan = PlanMeasurements(robot, pool, 20, options);
  ASSERT_EQ(plan.rows.size(), 20u);
  const Eigen::Vector3d tracker(2 * (0.1273 + 0.612 + 0.5723 + 0.163941 + 0.1157 + 0.0922 + 0.109), 0, 0.1273);
  EXPECT_TRUE(PoseConstraints(robot, options).tracker_position().isApprox(tracker, 1e-3));
  for (int i : plan.rows) EXPECT_EQ(IndependentViolation(robot, pool.q[i], options, tracker, 0.0, 200), "") << "row " << i;
  int rejected = 0;
  for (size_t i = 0; i < pool.q.size(); ++i) {
    if (std::find(plan.feasible.begin(), plan.feasible.end(), static_cast<int>(i)) != plan.feasible.end()) continue;
    ++rejected;
    EXPECT_NE(IndependentViolation(robot, pool.q[i], options, tracker, 0.02, 40), "")
        << "row " << i << ": " << PoseConstraints(robot, options).Violation(pool.q[i]);
  }
  EXPECT_GT(rejected, 0);
  EXPECT_GT(plan.feasible.size(), 20u);
}

TEST(PlanConstraints, SegmentDistanceMatchesSampling) {
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Vector3d v[4];
    for (auto& x : v) x = Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    if (trial % 10 == 0) v[1] = v[0];                       // a point against a segment
    if (trial % 10 == 1) v[3] = v[2] + 0.5 * (v[1] - v[0]);  // parallel segments
    const double exact = SegmentDistance(v[0], v[1], v[2], v[3]);
    const double sampled = SampledDistance(v[0], v[1], v[2], v[3]);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - 0.02);
  }
}

// Each greedy step picks the candidate whose addition scores best when the criterion is computed
// directly (ScoreDesign: an inverse, no update).
TEST(PlanSelection, GreedyStepsMaximiseTheDirectlyComputedCriterion) {
  const Robot robot = Ur10();
  PlanOptions options;
  options.generated_candidates = 60;
  options.tracker = false;
  const CandidatePool pool = GenerateCandidates(robot, options);
  for (const std::string criterion : {"D", "A", "I"}) {
    options.criterion = criterion;
    const PlanningProblem problem = PreparePlanning(robot, pool, options);
    std::vector<int> all(problem.model.rows.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    const std::vector<int> chosen = GreedySelect(problem.model, all, 4, criterion, problem.workspace);
    for (size_t k = 0; k < chosen.size(); ++k) {
      std::vector<int> set(chosen.begin(), chosen.begin() + k);
      double best = -std::numeric_limits<double>::infinity();
      int best_index = -1;
      for (int i : all) {
        if (std::find(set.begin(), set.end(), i) != set.end()) continue;
        set.push_back(i);
        const DesignScores s = ScoreDesign(problem.model, set, problem.workspace);
        set.pop_back();
        const double score = criterion == "D" ? s.log_det : criterion == "A" ? -s.trace_c : -s.trace_wc;
        if (score > best) best = score, best_index = i;
      }
      EXPECT_EQ(chosen[k], best_index) << criterion << " step " << k;
    }
  }
}

TEST(PlanTour, NoTwoOptMoveShortensThePlannedOrder) {
  const Robot robot = Ur10();
  ASSERT_EQ(robot.velocity_limits.size(), 6);
  PlanOptions options;
  options.generated_candidates = 40;
  const CandidatePool pool = GenerateCandidates(robot, options);
  const std::vector<int> order = OrderPoses(robot, pool.q);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < 40; ++i) ASSERT_EQ(sorted[i], i);
  const double t = PathTime(robot, pool.q, order);
  std::vector<int> identity(40);
  for (int i = 0; i < 40; ++i) identity[i] = i;
  EXPECT_LT(t, PathTime(robot, pool.q, identity));
  for (int i = 1; i < 40; ++i) {
    for (int j = i + 1; j < 40; ++j) {
      std::vector<int> other = order;
      std::reverse(other.begin() + i, other.begin() + j + 1);
      EXPECT_GE(PathTime(robot, pool.q, other), t - 1e-9);
    }
  }
  // The slowest joint's time: joint 1 (120 deg/s) moving 60 deg against joint 6 (180 deg/s) moving 90.
  Eigen::VectorXd a = Eigen::VectorXd::Zero(6), b = a;
  b[0] = 60 * kDegree;
  b[5] = 90 * kDegree;
  EXPECT_NEAR(MoveTime(robot, a, b), 0.5, 1e-12);
}

TEST(PlanCandidates, GeneratedOnesAreReproducibleAndWithinTheMargin) {
  const Robot robot = Ur10();
  PlanOptions options;
  options.generated_candidates = 50;
  const CandidatePool a = GenerateCandidates(robot, options), b = GenerateCandidates(robot, options);
  EXPECT_EQ(PoolRowsCsv(a, {0, 1, 2}), PoolRowsCsv(b, {0, 1, 2}));
  options.seed = 2;
  EXPECT_NE(PoolRowsCsv(a, {0}), PoolRowsCsv(GenerateCandidates(robot, options), {0}));
  for (const Eigen::VectorXd& q : a.q) {
    for (int j = 0; j < 6; ++j) EXPECT_LE(std::abs(q[j]), (360 - 5) * kDegree);
  }
}

}  // namespace
}  // namespace kincal::testing
