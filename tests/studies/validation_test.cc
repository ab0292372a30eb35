// Validation targets and the ISO 9283 characteristics.
#include <gtest/gtest.h>

#include "framework/math.h"
#include "studies/validation.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

TEST(Iso9283, PointsLieOnTheDiagonalPlaneAtTenPercentOfTheDiagonal) {
  const Eigen::Vector3d c(0.4, -0.1, 0.3);
  const double side = 0.2;
  const auto p = Iso9283Points(c, side);
  EXPECT_EQ(p[0], c);
  const double half_diagonal = std::sqrt(3.0) * side / 2;
  for (int i = 1; i < 5; ++i) {
    const Eigen::Vector3d d = p[i] - c;
    EXPECT_NEAR(d.norm(), 0.8 * half_diagonal, 1e-15);  // 10 % of the full diagonal from the corner
    EXPECT_NEAR(d.x(), d.y(), 1e-15);                   // the plane through the edges (-x,-y) and (+x,+y)
    EXPECT_NEAR(std::abs(d.z()), 0.4 * side, 1e-15);
  }
  // Opposite points are symmetric about the centre.
  EXPECT_TRUE((p[1] - c).isApprox(-(p[3] - c)));
  EXPECT_TRUE((p[2] - c).isApprox(-(p[4] - c)));
}

TEST(Iso9283, AccuracyAndRepeatabilityOfKnownAttainedPoses) {
  Eigen::Isometry3d commanded = Eigen::Isometry3d::Identity();
  commanded.translation() = Eigen::Vector3d(0.5, 0.0, 0.2);
  const int n = 10;
  const double d = 1e-4, eps = 1e-3;
  std::vector<Eigen::Isometry3d> attained;
  for (int j = 0; j < n; ++j) {
    const double sign = j % 2 ? 1.0 : -1.0;
    Eigen::Isometry3d T = commanded;
    T.translation() += Eigen::Vector3d(2e-3, sign * d, 0.0);  // offset 2 mm in x, scatter d in y
    T.linear() = RotationExp(Eigen::Vector3d(0.01, 0.0, sign * eps)) * commanded.linear();
    attained.push_back(T);
  }
  const Iso9283PoseStats s = ComputeIso9283(commanded, attained);
  EXPECT_EQ(s.cycles, n);
  EXPECT_NEAR(s.ap_p, 2e-3, 1e-15);
  EXPECT_NEAR(s.rp_l, d, 1e-15);  // every l_j = d: S_l = 0
  EXPECT_NEAR(s.ap_abc[0], 0.01, 1e-9);
  EXPECT_NEAR(s.ap_abc[2], 0.0, 1e-9);
  // a_j = +-eps about a mean of 0: S = eps sqrt(n / (n - 1)).
  EXPECT_NEAR(s.rp_abc[2], 3 * eps * std::sqrt(n / (n - 1.0)), 1e-8);
  EXPECT_THROW(ComputeIso9283(commanded, {commanded}), std::invalid_argument);
}

TEST(Iso9283, CubeIsPlacedWhereTheNominalRobotReachesEveryPose) {
  const Robot robot = testing::SeedNominal();
  Iso9283Spec spec;
  spec.side = 0.2;
  const Iso9283Cube cube = PlaceIso9283Cube(robot, spec, true, 3);
  ASSERT_EQ(cube.poses.size(), 5u);
  const auto points = Iso9283Points(cube.center, 0.2);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(cube.poses[i].q_nominal);
    EXPECT_LT((T.translation() - points[i]).norm(), 1e-9);
    EXPECT_LT(RotationAngleBetween(T.linear(), cube.poses[0].T_meas_tool.linear()), 1e-9);  // one orientation
    for (int j = 0; j < robot.dof(); ++j) {
      EXPECT_GE(cube.poses[i].q_nominal[j], robot.Limit(j).first);
      EXPECT_LE(cube.poses[i].q_nominal[j], robot.Limit(j).second);
    }
  }
  // Deterministic, and a cube larger than the arm fits nowhere.
  EXPECT_EQ(PlaceIso9283Cube(robot, spec, true, 3).center, cube.center);
  spec.side = 3.0;
  EXPECT_THROW(PlaceIso9283Cube(robot, spec, true, 3), std::invalid_argument);
}

TEST(RandomTargets, AreTheNominalPosesOfCommandsWithinLimits) {
  const Robot robot = testing::SeedNominal();
  const std::vector<std::pair<double, double>> limits(6, {-0.5, 0.5});
  const auto targets = RandomTargets(robot, 50, limits, 11);
  ASSERT_EQ(targets.size(), 50u);
  for (const auto& t : targets) {
    EXPECT_TRUE(t.T_meas_tool.isApprox(robot.model().ForwardKinematics(t.q_nominal), 1e-15));
    EXPECT_LE(t.q_nominal.cwiseAbs().maxCoeff(), 0.5);
  }
  EXPECT_EQ(RandomTargets(robot, 50, limits, 11)[49].q_nominal, targets[49].q_nominal);
  EXPECT_NE(RandomTargets(robot, 50, limits, 12)[49].q_nominal, targets[49].q_nominal);
}

// The real arm reaches every target (its pose at joints within the limits), and the nominal solution
// reaches it on the nominal arm.
TEST(RandomTargets, ReachableTargetsAreTheTruthsPosesWithTheNominalSolution) {
  const Robot nominal = testing::SeedNominal(), truth = testing::SeedTruth();
  const auto targets = ReachableRandomTargets(nominal, truth, 200, {}, true, 5);
  ASSERT_EQ(targets.size(), 200u);
  for (const auto& t : targets) {
    const Eigen::Isometry3d T = nominal.model().ForwardKinematics(t.q_nominal);
    EXPECT_LT((T.translation() - t.T_meas_tool.translation()).norm(), 1e-9);
    EXPECT_LT(RotationAngleBetween(T.linear(), t.T_meas_tool.linear()), 1e-9);
    for (int j = 0; j < 6; ++j) {
      EXPECT_GE(t.q_nominal[j], nominal.Limit(j).first);
      EXPECT_LE(t.q_nominal[j], nominal.Limit(j).second);
    }
  }
  EXPECT_EQ(ReachableRandomTargets(nominal, truth, 200, {}, true, 5)[199].q_nominal, targets[199].q_nominal);
}

}  // namespace
}  // namespace kincal
