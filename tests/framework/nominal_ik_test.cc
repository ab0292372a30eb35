// Inverse kinematics of the nominal robot: closed form against forward kinematics on random
// configurations of four real arms (every branch), branch counts, poses on a fold of the workspace
// (two branches meeting), detection from the geometry (an arm without a closed form goes numeric),
// limits with 2 pi wraps, the singular status against the singular values, and unreachable targets
// without NaN.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SVD>

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

// Configurations where the Jacobian's determinant changes sign along one joint (bisected to rounding):
// their poses lie on a fold of the workspace, where two branches meet and the closed form's
// polynomial has a double root. Each such pose is still solved in closed form, to 1e-9, next to the
// configuration it came from.
std::vector<Eigen::VectorXd> FoldConfigurations(const Robot& robot, int joint, int count, uint64_t seed) {
  const auto det = [&](const Eigen::VectorXd& q) {
    return Eigen::Matrix<double, 6, 6>(robot.model().JointJacobian(q)).determinant();
  };
  std::vector<Eigen::VectorXd> out;
  Rng rng(seed);
  while (static_cast<int>(out.size()) < count) {
    const Eigen::VectorXd q = RandomConfiguration(robot, &rng);
    const auto [low, high] = robot.Limit(joint);
    for (int s = 0; s < 50 && static_cast<int>(out.size()) < count; ++s) {
      Eigen::VectorXd a = q, b = q;
      a[joint] = low + (high - low) * s / 50;
      b[joint] = low + (high - low) * (s + 1) / 50;
      const double sign = det(a);
      if (sign * det(b) > 0) continue;
      for (int it = 0; it < 60; ++it) {
        Eigen::VectorXd m = a;
        m[joint] = 0.5 * (a[joint] + b[joint]);
        (det(m) * sign > 0 ? a : b) = m;
      }
      out.push_back(a);
    }
  }
  return out;
}

TEST(NominalIk, PosesOnAFoldAreSolvedInClosedForm) {
  // The shoulder and elbow folds of the Puma 560 (its first two axes meet: the eliminant has only
  // double roots; with its shoulder offset every fold is a true fold, the configuration unique), the
  // IRB 120's along joint 3 (some where its wrist centre crosses axis 1: a continuum in q1, any member
  // will do), and the wrist folds of the seed's arm (the general eliminant; axes 3 and 5 in line: a
  // continuum too).
  const struct {
    const char* file;
    int joint;
    bool unique;
  } cases[] = {{"puma560_dh.yaml", 1, true}, {"puma560_dh.yaml", 2, true}, {"irb120_mdh.yaml", 2, false},
               {"seed_nominal.yaml", 4, false}};
  for (const auto& c : cases) {
    const Robot robot = LoadExampleRobot(c.file);
    const NominalInverseKinematics ik(robot);
    int near = 0;
    const std::vector<Eigen::VectorXd> folds = FoldConfigurations(robot, c.joint, 30, 21);
    for (const Eigen::VectorXd& q : folds) {
      const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
      const IkSolution s = ik.Solve(T, q);
      EXPECT_TRUE(s.closed_form) << c.file << " " << q.transpose();
      const Vector6d e = PoseError(robot.model().ForwardKinematics(s.q), T);
      EXPECT_LT(e.head<3>().norm(), 1e-9) << c.file;
      EXPECT_LT(e.tail<3>().norm(), 1e-9) << c.file;
      near += MaxWrappedDifference(s.q, q) < 1e-6;
    }
    if (c.unique) EXPECT_GE(near, 29) << c.file << " joint " << c.joint + 1;
  }
}

// The singular status is sigma_min / sigma_max < singular_ratio of the Jacobian, also next to the
// threshold (the solver brackets the ratio without an SVD and decides by SVD only near it).
TEST(NominalIk, SingularStatusFollowsTheSingularValues) {
  const Robot robot = LoadExampleRobot("puma560_dh.yaml");
  const NominalInverseKinematics ik(robot);
  Rng rng(13);
  int singular = 0, regular = 0;
  for (int trial = 0; trial < 120; ++trial) {
    Eigen::VectorXd q = RandomConfiguration(robot, &rng);
    q[4] = std::pow(10.0, rng.Uniform(-9, -3)) * (trial % 2 ? 1 : -1);  // axes 4 and 6 nearly in line
    const IkSolution s = ik.Solve(robot.model().ForwardKinematics(q), q);
    ASSERT_TRUE(s.status == IkStatus::kSolved || s.status == IkStatus::kSingular) << ToString(s.status);
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(robot.model().JointJacobian(s.q)).singularValues();
    const double ratio = sv[5] / sv[0];
    if (std::abs(ratio / 1e-6 - 1) < 1e-6) continue;  // too close to call
    EXPECT_EQ(s.status == IkStatus::kSingular, ratio < 1e-6) << ratio;
    (ratio < 1e-6 ? singular : regular) += 1;
  }
  EXPECT_GT(singular, 20);
  EXPECT_GT(regular, 20);
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
