// Tracker points as distances, and the score by distances between points: exact on the truth in any
// frame, not zero on an arm with a wrong link.
#include <gtest/gtest.h>

#include "framework/math.h"
#include "robot/instrument_scoring.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

TEST(InstrumentScoring, PointsBecomeDistancesToThePivotsInTurn) {
  const Robot robot = testing::LoadExampleRobot("irb120_mdh.yaml");
  Dataset points = testing::RandomPoses(robot, robot, 7, 3);
  points.rows[2].split = Split::kTest;
  const std::vector<Eigen::Vector3d> pivots = {{0.7, 0, 0.2}, {0, 0.7, 0.3}};
  const Dataset d = DistancesFromPoints(points, pivots, {"A", "B"});
  ASSERT_EQ(d.rows.size(), 7u);
  for (size_t i = 0; i < d.rows.size(); ++i) {
    EXPECT_EQ(d.rows[i].kind, MeasurementKind::kDistance);
    EXPECT_EQ(d.rows[i].fixture, i % 2 ? "B" : "A");
    EXPECT_DOUBLE_EQ(d.rows[i].distance, (points.rows[i].p - pivots[i % 2]).norm());
    EXPECT_EQ(d.rows[i].q, points.rows[i].q);
  }
  EXPECT_EQ(d.rows[2].split, Split::kTest);
  d.Validate(robot.dof());
  EXPECT_THROW(DistancesFromPoints(d, pivots, {"A", "B"}), std::invalid_argument);
  EXPECT_THROW(DistancesFromPoints(points, pivots, {"A"}), std::invalid_argument);
}

TEST(InstrumentScoring, DistancesBetweenPointsIgnoreTheFrameButSeeTheArm) {
  const Robot truth = testing::LoadExampleRobot("irb120_as_measured.yaml");
  const Dataset points = testing::RandomPoses(truth, truth, 40, 5);
  Robot moved = truth;
  moved.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(0.3, -2.0, 0.5), Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_LT(PairwiseDistanceErrors(truth, moved, points).max, 1e-12);
  Robot longer = truth;
  longer.model().SetParameter("a_3", longer.model().Parameter("a_3") + 1e-3);
  const ErrorStats e = PairwiseDistanceErrors(truth, longer, points);
  EXPECT_EQ(e.count, 40 * 39 / 2);
  EXPECT_GT(e.rms, 1e-4);
  EXPECT_LT(e.max, 2.1e-3);  // a 1 mm longer link moves no distance by more than twice that
}

}  // namespace
}  // namespace kincal
