// Inverse kinematics of the nominal robot: closed form against forward kinematics on random
// configurations of four real arms (every branch), branch counts, detection from the geometry (an arm
// without a closed form goes numeric), limits with 2 pi wraps, and unreachable targets without NaN.
#include <gtest/gtest.h>

#include "framework/math.h"
#include "framework/nominal_ik.h"
#include "framework/random.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::LoadExampleRobot;

Eigen::VectorXd RandomConfiguration(const Robot& robot, Rng* rng) {
  Eigen::VectorXd q(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) {
    const auto [low, high] = robot.Limit(j);
    q[j] = rng->Uniform(low, high);
  }
  return q;
}

double MaxWrappedDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double d = 0.0;
  for (int j = 0; j < a.size(); ++j) d = std::max(d, std::abs(WrapAngle(a[j] - b[j])));
  return d;
}

struct ArmCase {
  const char* file;
  const char* method;
};

class ClosedForm : public ::testing::TestWithParam<ArmCase> {};

// Every branch reaches the pose to 1e-9, one of them is the configuration the pose came from, and
// Solve from the true configuration as reference returns it.
TEST_P(ClosedForm, EveryBranchRoundTripsThroughForwardKinematics) {
  const Robot robot = LoadExampleRobot(GetParam().file);
  const NominalInverseKinematics ik(robot);
  EXPECT_EQ(ik.method(), GetParam().method);
  Rng rng(3);
  int max_branches = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(robot, &rng);
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const std::vector<IkSolution> all = ik.AllBranches(T, q);
    ASSERT_FALSE(all.empty()) << trial;
    bool found_truth = false;
    for (const IkSolution& s : all) {
      const Vector6d e = PoseError(robot.model().ForwardKinematics(s.q), T);
      EXPECT_LT(e.head<3>().norm(), 1e-9) << trial;
      EXPECT_LT(e.tail<3>().norm(), 1e-9) << trial;
      found_truth = found_truth || MaxWrappedDifference(s.q, q) < 1e-6;
    }
    EXPECT_TRUE(found_truth) << trial;
    max_branches = std::max<int>(max_branches, static_cast<int>(all.size()));
    const IkSolution s = ik.Solve(T, q);
    EXPECT_TRUE(s.closed_form);
    EXPECT_TRUE(s.status == IkStatus::kSolved || s.status == IkStatus::kSingular) << ToString(s.status);
    EXPECT_LT((s.q - q).cwiseAbs().maxCoeff(), 1e-6) << trial;
  }
  // 8 branches for a generic arm of either family at a generic pose.
  EXPECT_EQ(max_branches, 8);
}

INSTANTIATE_TEST_SUITE_P(Arms, ClosedForm,
                         ::testing::Values(ArmCase{"seed_nominal.yaml", "pieper(3,4,5)"},
                                           ArmCase{"irb120_mdh.yaml", "pieper(4,5,6)"},
                                           ArmCase{"puma560_dh.yaml", "pieper(4,5,6)"},
                                           ArmCase{"ur10_dh.yaml", "parallel(2,3,4)"}),
                         [](const auto& info) { return std::string(info.param.method).substr(0, 6) + std::to_string(info.index); });

// A generic Pieper arm (offsets everywhere, skewed axes, a base and a tool) has 8 branches.
TEST(NominalIk, GenericPieperArmHasEightBranches) {
  Robot robot = LoadExampleRobot("seed_nominal.yaml");
  robot.model().SetParameter("a_2", 0.31);
  robot.model().SetParameter("alpha_2", 1.2);
  robot.model().SetParameter("d_2", 0.07);
  robot.model().SetParameter("a_3", 0.05);
  robot.model().SetBase(PoseFromXyzRpy({1.5, -0.2, 0.3}, {0.1, -0.2, 0.3}));
  const NominalInverseKinematics ik(robot);
  ASSERT_TRUE(ik.has_closed_form()) << ik.method();
  Rng rng(5);
  int eights = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(robot, &rng);
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const std::vector<IkSolution> all = ik.AllBranches(T, q);
    for (const IkSolution& s : all) {
      EXPECT_LT(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
    }
    eights += all.size() == 8;
    EXPECT_LE(all.size(), 8u);
  }
  EXPECT_GT(eights, 0);
}

// Breaking the intersection (an offset on the wrist) leaves no closed form: numeric, still solving.
TEST(NominalIk, ArmWithoutClosedFormGoesNumeric) {
  Robot robot = LoadExampleRobot("irb120_mdh.yaml");
  robot.model().SetParameter("d_5", 0.02);  // axis 5 no longer meets axes 4 and 6
  const NominalInverseKinematics ik(robot);
  EXPECT_EQ(ik.method(), "numeric");
  Robot ur = LoadExampleRobot("ur10_dh.yaml");
  ur.model().SetParameter("alpha_2", 0.01);  // axes 2 and 3 no longer parallel
  EXPECT_EQ(NominalInverseKinematics(ur).method(), "numeric");
  Rng rng(9);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(robot, &rng);
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const IkSolution s = ik.Solve(T, Eigen::VectorXd());
    EXPECT_FALSE(s.closed_form);
    if (s.status == IkStatus::kSolved) EXPECT_LT(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
  }
}

TEST(NominalIk, PrefersTheBranchClosestToTheReferenceAndWrapsIntoLimits) {
  const Robot robot = LoadExampleRobot("ur10_dh.yaml");  // +-360 deg: two representatives per angle
  const NominalInverseKinematics ik(robot);
  Eigen::VectorXd q(6);
  q << 0.3, -1.2, 1.1, -0.5, 1.4, 0.2;
  const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
  Eigen::VectorXd reference = q;
  reference[5] -= 2 * M_PI - 0.1;  // next to q6 - 2 pi (inside the +-2 pi limits)
  const IkSolution s = ik.Solve(T, reference);
  ASSERT_EQ(s.status, IkStatus::kSolved);
  EXPECT_NEAR(s.q[5], q[5] - 2 * M_PI, 1e-9);
  EXPECT_NEAR(s.q[0], q[0], 1e-9);
  // Without a reference: the branch closest to the middle of the limits (0 here), inside the limits.
  const IkSolution mid = ik.Solve(T, Eigen::VectorXd());
  for (int j = 0; j < 6; ++j) EXPECT_LE(std::abs(mid.q[j]), M_PI + 1e-9);
}

TEST(NominalIk, NamedConfigurationSelectsTheBranch) {
  const Robot robot = LoadExampleRobot("puma560_dh.yaml");
  Eigen::VectorXd q(6);
  q << 0.2, -0.6, 0.4, 0.5, 0.8, -0.3;
  const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
  NominalIkOptions options;
  options.configuration = {0, 0, 0, 0, -1, 0};  // the other wrist flip
  const IkSolution s = NominalInverseKinematics(robot, options).Solve(T, q);
  ASSERT_EQ(s.status, IkStatus::kSolved) << ToString(s.status);
  EXPECT_LT(WrapAngle(s.q[4]), 0.0);
  EXPECT_LT(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
}

TEST(NominalIk, UnreachableAndOutOfLimitsGetTheirStatusAndFiniteJoints) {
  const Robot robot = LoadExampleRobot("irb120_mdh.yaml");
  NominalIkOptions options;
  options.numeric.restarts = 3;
  const NominalInverseKinematics ik(robot, options);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 5.0, 0.0, 0.0;
  const IkSolution s = ik.Solve(far, Eigen::VectorXd());
  EXPECT_EQ(s.status, IkStatus::kUnreachable);
  EXPECT_TRUE(s.q.allFinite());
  EXPECT_TRUE(std::isfinite(s.position_error));
  EXPECT_GT(s.position_error, 4.0);
  // Every solution of this pose needs joint 1 outside its limits.
  Robot narrow = robot;
  narrow.limits.assign(6, {-M_PI, M_PI});
  narrow.limits[0] = {-0.1, 0.1};
  Eigen::VectorXd q(6);
  q << 1.0, 0.2, 0.1, 0.3, 0.5, 0.2;
  const IkSolution o = NominalInverseKinematics(narrow, options).Solve(narrow.model().ForwardKinematics(q), Eigen::VectorXd());
  EXPECT_EQ(o.status, IkStatus::kOutOfLimits) << ToString(o.status);
  EXPECT_TRUE(o.q.allFinite());
}

TEST(NominalIk, SingularPoseIsReportedSingular) {
  const Robot robot = LoadExampleRobot("puma560_dh.yaml");
  Eigen::VectorXd q(6);
  q << 0.3, -0.4, 0.2, 0.6, 0.0, 0.4;  // q5 = 0: axes 4 and 6 aligned
  const IkSolution s = NominalInverseKinematics(robot).Solve(robot.model().ForwardKinematics(q), q);
  EXPECT_EQ(s.status, IkStatus::kSingular);
  EXPECT_TRUE(s.q.allFinite());
  EXPECT_LT(PoseError(robot.model().ForwardKinematics(s.q), robot.model().ForwardKinematics(q)).norm(), 1e-9);
}

}  // namespace
}  // namespace kincal
