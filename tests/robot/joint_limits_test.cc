// WrapIntoLimits (robot/robot.h): the one rule by which the inverse kinematics, the compensators and
// their restarts place revolute joints (whole turns into the limits, nearest a reference) and snap a
// solution that lies on a limit to rounding.
#include <cmath>

#include <gtest/gtest.h>

#include "robot/robot.h"
#include "models/mdh_model.h"

namespace kincal {
namespace {

Robot TwoJoints(double low, double high) {
  Robot robot("two", std::make_unique<MdhModel>(std::vector<JointType>{JointType::kRevolute, JointType::kPrismatic}));
  robot.limits = {{low, high}, {0.0, 0.5}};
  return robot;
}

constexpr double kTurn = 2 * M_PI;

TEST(WrapIntoLimits, TheTurnNearestTheReferenceInsideTheLimits) {
  const Robot robot = TwoJoints(-400 * M_PI / 180, 400 * M_PI / 180);  // more than a turn: a choice
  const Eigen::VectorXd reference = (Eigen::VectorXd(2) << 5.0, 0.1).finished();
  Eigen::VectorXd q = (Eigen::VectorXd(2) << 0.3 - kTurn, 0.2).finished();
  EXPECT_TRUE(WrapIntoLimits(robot, &reference, q));
  EXPECT_NEAR(q[0], 0.3 + kTurn, 1e-12);  // 6.58 is inside (<= 6.98) and nearest 5.0
  EXPECT_EQ(q[1], 0.2);                   // prismatic: as it was
  // The nearest turn itself outside: the nearest inside.
  const Eigen::VectorXd far = (Eigen::VectorXd(2) << 12.0, 0.1).finished();
  q[0] = 0.3;
  EXPECT_TRUE(WrapIntoLimits(robot, &far, q));
  EXPECT_NEAR(q[0], 0.3 + kTurn, 1e-12);
  // No reference: the representative nearest q's own value, which is q when it is inside.
  q[0] = -0.3;
  EXPECT_TRUE(WrapIntoLimits(robot, nullptr, q));
  EXPECT_EQ(q[0], -0.3);
  q[0] = -0.3 + 2 * kTurn;  // outside: one turn down is the nearest inside
  EXPECT_TRUE(WrapIntoLimits(robot, nullptr, q));
  EXPECT_NEAR(q[0], -0.3 + kTurn, 1e-12);
}

TEST(WrapIntoLimits, OnALimitToRoundingIsOnIt) {
  const Robot robot = TwoJoints(-1.0, 1.0);
  Eigen::VectorXd q = (Eigen::VectorXd(2) << 1.0 + 5e-10 - kTurn, 0.5 + 5e-10).finished();
  bool clamped = false;
  EXPECT_FALSE(WrapIntoLimits(robot, nullptr, q));  // no slack: outside
  EXPECT_TRUE(WrapIntoLimits(robot, nullptr, q, 1e-9, &clamped));
  EXPECT_TRUE(clamped);
  EXPECT_EQ(q[0], 1.0);
  EXPECT_EQ(q[1], 0.5);
}

TEST(WrapIntoLimits, NoTurnInsideGoesNearestTheLimits) {
  const Robot robot = TwoJoints(-1.0, 1.0);
  Eigen::VectorXd q = (Eigen::VectorXd(2) << 1.5 + 3 * kTurn, 0.2).finished();
  bool clamped = false;
  EXPECT_FALSE(WrapIntoLimits(robot, nullptr, q, 1e-9, &clamped));
  EXPECT_NEAR(q[0], 1.5, 1e-12);  // 0.5 rad above the upper limit, against 2 pi - 2.5 below the lower
  EXPECT_FALSE(clamped);
  q[0] = -1.2 - kTurn;
  EXPECT_FALSE(WrapIntoLimits(robot, nullptr, q));
  EXPECT_NEAR(q[0], -1.2, 1e-12);
}

}  // namespace
}  // namespace kincal
