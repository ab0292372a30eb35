// Inverse kinematics of the nominal robot: closed form against forward kinematics on random
// configurations of four real arms (every branch), branch counts, poses on a fold of the workspace
// (two branches meeting), structured configurations (joints on multiples of 45 and 90 deg: singular
// poses, continua of solutions, joints on their limits) solved or singular to 1e-9 with the status
// that the singular values give, the free joint of a continuum at the reference (and moved only as far
// as the limits require), detection from the geometry (an arm without a closed form goes numeric),
// the numeric solver on arms without a closed form (random 6R and 7R geometry, a 7-joint arm) and at
// singular configurations, limits with 2 pi wraps, and unreachable targets without NaN.
#include <sstream>

#include <gtest/gtest.h>

#include <Eigen/LU>

#include "robot/inverse_kinematics.h"
#include "framework/math.h"
#include "robot/nominal_ik.h"
#include "framework/random.h"
#include "framework/svd.h"
#include "robot/robot_file.h"
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

INSTANTIATE_TEST_SUITE_P(
    Arms, ClosedForm,
    ::testing::Values(ArmCase{"seed_nominal.yaml", "pieper(3,4,5)"}, ArmCase{"irb120_mdh.yaml", "pieper(4,5,6)"},
                      ArmCase{"puma560_dh.yaml", "pieper(4,5,6)"}, ArmCase{"ur10_dh.yaml", "parallel(2,3,4)"}),
    [](const auto& info) { return std::string(info.param.method).substr(0, 6) + std::to_string(info.index); });

// Every joint a multiple of `step` inside its limits, drawn uniformly from that grid.
Eigen::VectorXd GridConfiguration(const Robot& robot, double step, Rng* rng) {
  Eigen::VectorXd q(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) {
    const auto [low, high] = robot.Limit(j);
    const double k_low = std::ceil(low / step - 1e-9), k_high = std::floor(high / step + 1e-9);
    const double k = std::min(k_high, k_low + std::floor(rng->Uniform(0, k_high - k_low + 1)));
    q[j] = std::clamp(k * step, low, high);  // a limit on the grid, to the last bit
  }
  return q;
}

double SigmaRatio(const Robot& robot, const Eigen::VectorXd& q) {
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(robot.model().JointJacobian(q)).singularValues();
  return sv[sv.size() - 1] / sv[0];
}

bool InsideLimits(const Robot& robot, const Eigen::VectorXd& q) {
  for (int j = 0; j < q.size(); ++j) {
    if (q[j] < robot.Limit(j).first || q[j] > robot.Limit(j).second) return false;
  }
  return true;
}

// Structured configurations: wrists with two axes in line (a continuum: only the sum of two angles
// matters), arms stretched or folded, axes parallel to others or meeting them, joints on their limits.
// Before the singular poses were solved in closed form, 7-27 % of these poses on the seed's arm came
// back unreachable (1e-7 m off) or out of limits. Every pose is reached in closed form to 1e-9 m and
// 1e-9 rad inside the limits, `singular` exactly where sigma_min / sigma_max < 1e-6: from the middle of
// the limits, and as a program (the previous target's solution as reference).
TEST_P(ClosedForm, StructuredConfigurationsAreSolvedOrSingular) {
  const Robot robot = LoadExampleRobot(GetParam().file);
  const NominalInverseKinematics ik(robot);
  Rng rng(31);
  int singular = 0, solved = 0;
  Eigen::VectorXd previous;
  for (int trial = 0; trial < 1200; ++trial) {
    const bool program = trial >= 400 && trial < 800;
    const Eigen::VectorXd q = GridConfiguration(robot, (trial < 800 ? 45 : 90) * M_PI / 180, &rng);
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const IkSolution s = ik.Solve(T, program ? previous : Eigen::VectorXd());
    previous = s.q;
    ASSERT_TRUE(s.status == IkStatus::kSolved || s.status == IkStatus::kSingular)
        << ToString(s.status) << " at " << (q * 180 / M_PI).transpose();
    EXPECT_TRUE(s.closed_form) << (q * 180 / M_PI).transpose();
    const Vector6d e = PoseError(robot.model().ForwardKinematics(s.q), T);
    EXPECT_LE(e.head<3>().norm(), 1e-9) << (q * 180 / M_PI).transpose();
    EXPECT_LE(e.tail<3>().norm(), 1e-9) << (q * 180 / M_PI).transpose();
    EXPECT_TRUE(InsideLimits(robot, s.q)) << (s.q * 180 / M_PI).transpose();
    const double ratio = SigmaRatio(robot, s.q);
    if (std::abs(ratio / 1e-6 - 1) > 1e-3) {
      EXPECT_EQ(s.status == IkStatus::kSingular, ratio < 1e-6) << ratio;
    }
    (s.status == IkStatus::kSingular ? singular : solved) += 1;
  }
  EXPECT_GT(singular, 50);
  EXPECT_GT(solved, 50);
}

// A wrist with two axes in line (Puma 560: q5 = 0, axes 4 and 6; the seed's arm: q4 = 0, axes 3 and 5):
// every split of the sum between the two reaches the pose. The first of the pair stays at the
// reference's value, the other takes the rest, the joints before the wrist are the pose's. With three
// parallel axes (UR10, q5 = 0: axes 4 and 6 parallel, offset), the free angle moves the elbow too:
// joint 6 stays at the reference's value and the other five follow.
TEST(NominalIk, FreeJointOfASingularPoseStaysAtTheReference) {
  const double deg = M_PI / 180;
  const struct {
    const char* file;
    double q[6];
    int free, partner;  // 0-based; partner -1: not a plain sum
    double shift;
  } cases[] = {{"puma560_dh.yaml", {20, 30, -60, 50, 0, 40}, 3, 5, 0.3},
               {"seed_nominal.yaml", {20, 30, -60, 0, -90, 40}, 2, 4, 0.3},
               {"ur10_dh.yaml", {30, -60, 50, 20, 0, 10}, 5, -1, 0.5}};
  for (const auto& c : cases) {
    const Robot robot = LoadExampleRobot(c.file);
    const NominalInverseKinematics ik(robot);
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(c.q, 6) * deg;
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    Eigen::VectorXd reference = q;
    reference[c.free] += c.shift;
    const IkSolution s = ik.Solve(T, reference);
    ASSERT_EQ(s.status, IkStatus::kSingular) << c.file << " " << ToString(s.status);
    EXPECT_TRUE(s.closed_form) << c.file;
    EXPECT_LE(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9) << c.file;
    EXPECT_NEAR(s.q[c.free], reference[c.free], 1e-9) << c.file;
    if (c.partner < 0) continue;
    const int first = std::min(c.free, c.partner);
    for (int j = 0; j < first; ++j) EXPECT_NEAR(s.q[j], q[j], 1e-9) << c.file << " joint " << j + 1;
    EXPECT_NEAR(WrapAngle(s.q[first + 1] - q[first + 1]), 0.0, 1e-9) << c.file;  // the joint between the pair
    // The pair turns about one line: one angle gained is one lost by the other (same or opposite sense).
    const double moved = WrapAngle(s.q[c.partner] - q[c.partner]);
    EXPECT_NEAR(std::abs(moved), c.shift, 1e-9) << c.file;
  }
}

// The seed's arm at q4 = 0 with q3 + q5 = -150 deg and no reference: q3 at the middle of its limits (0)
// would need q5 = -150 deg, beyond its -120. The free joint moves as little as the limits require: q3 =
// -30, q5 = -120, exactly on the limit.
TEST(NominalIk, FreeJointMovesOnlyAsFarAsTheLimitsRequire) {
  const Robot robot = LoadExampleRobot("seed_nominal.yaml");
  const double deg = M_PI / 180;
  Eigen::VectorXd q(6);
  q << 20 * deg, 30 * deg, -60 * deg, 0, -90 * deg, 40 * deg;
  const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
  const IkSolution s = NominalInverseKinematics(robot).Solve(T, Eigen::VectorXd());
  ASSERT_EQ(s.status, IkStatus::kSingular) << ToString(s.status);
  EXPECT_NEAR(s.q[4], -120 * deg, 1e-9);
  EXPECT_NEAR(s.q[2], -30 * deg, 1e-9);
  EXPECT_TRUE(InsideLimits(robot, s.q));
  const Vector6d e = PoseError(robot.model().ForwardKinematics(s.q), T);
  EXPECT_LE(e.head<3>().norm(), 1e-12);
  EXPECT_LE(e.tail<3>().norm(), 1e-12);
}

// UR10 stretched (q3 = 0) with its wrist singular (q5 = 180 deg, q4 = -90): of the continuum that the
// wrist alone would allow, the elbow reaches one member only. Solved in closed form from the middle of
// the limits, whose value of the free joint the elbow does not reach. The angles in several turns
// (each rounds differently; the closed form used to miss some by 3e-7 m).
TEST(NominalIk, SingularWristWithTheElbowStretchedIsSolvedInClosedForm) {
  const Robot robot = LoadExampleRobot("ur10_dh.yaml");
  const NominalInverseKinematics ik(robot);
  for (int k = 0; k < 64; ++k) {
    Eigen::VectorXd q(6);
    q << -90 + 90 * (k % 4), k & 4 ? -315 : 45, k & 8 ? 360 : 0, -90, k & 16 ? -180 : 180, k & 32 ? -270 : 90;
    q = q * M_PI / 180;
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const IkSolution s = ik.Solve(T, Eigen::VectorXd());
    ASSERT_EQ(s.status, IkStatus::kSingular) << ToString(s.status) << " at " << (q * 180 / M_PI).transpose();
    EXPECT_TRUE(s.closed_form);
    EXPECT_LE(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
  }
}

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
  } cases[] = {{"puma560_dh.yaml", 1, true},
               {"puma560_dh.yaml", 2, true},
               {"irb120_mdh.yaml", 2, false},
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
    if (c.unique) {
      EXPECT_GE(near, 29) << c.file << " joint " << c.joint + 1;
    }
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
    if (s.status == IkStatus::kSolved) {
      EXPECT_LT(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
    }
  }
}

// An arm of random geometry (modified DH, every angle and length drawn), limits of +-170 deg and a tool.
Robot RandomArm(int joints, uint64_t seed) {
  Rng rng(seed);
  std::ostringstream yaml;
  yaml << "name: random\nconvention: mdh\nunits: {length: m, angle: deg}\njoints:\n";
  for (int j = 0; j < joints; ++j) {
    yaml << "  - {alpha: " << rng.Uniform(-180, 180) << ", a: " << (j ? rng.Uniform(0, 0.4) : 0.0)
         << ", theta: " << rng.Uniform(-180, 180) << ", d: " << rng.Uniform(0, 0.4) << "}\n";
  }
  yaml << "limits: [";
  for (int j = 0; j < joints; ++j) yaml << (j ? ", " : "") << "[-170, 170]";
  yaml << "]\ntool: {xyz: [0.05, 0.02, 0.1], rpy: [0, 0, 0]}\n";
  return ParseRobotYaml(yaml.str(), "random.yaml");
}

// A 7-joint arm like the KUKA LBR iiwa: spherical shoulder and wrist, one redundant joint.
Robot SevenJointArm() {
  return ParseRobotYaml(R"(name: seven
convention: dh
units: {length: m, angle: deg}
joints:
  - {alpha: -90, a: 0, theta: 0, d: 0.36}
  - {alpha: 90, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 0, theta: 0, d: 0.42}
  - {alpha: -90, a: 0, theta: 0, d: 0}
  - {alpha: -90, a: 0, theta: 0, d: 0.4}
  - {alpha: 90, a: 0, theta: 0, d: 0}
  - {alpha: 0, a: 0, theta: 0, d: 0.126}
limits: [[-170, 170], [-120, 120], [-170, 170], [-120, 120], [-170, 170], [-120, 120], [-175, 175]]
)",
                        "seven.yaml");
}

// Arms without a closed form: the numeric solver (Levenberg-Marquardt, restarts from random
// configurations within the limits) reaches >= 99.9 % of the poses of random configurations, from the
// middle of the limits, to 1e-9 m and 1e-9 rad inside the limits. (The damped Newton it replaced, with 20
// restarts: 98.6-99.95 % on such arms, by stalls and solutions outside the limits.)
TEST(NominalIk, NumericSolverReachesArmsWithoutClosedForm) {
  const Robot arms[] = {RandomArm(6, 3), RandomArm(7, 102), SevenJointArm()};
  for (const Robot& robot : arms) {
    const NominalInverseKinematics ik(robot);
    ASSERT_EQ(ik.method(), "numeric");
    Rng rng(17);
    int reached = 0;
    constexpr int kTargets = 1000;
    for (int trial = 0; trial < kTargets; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(robot, &rng);
      const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
      const IkSolution s = ik.Solve(T, Eigen::VectorXd());
      ASSERT_TRUE(s.q.allFinite());
      const Vector6d e = PoseError(robot.model().ForwardKinematics(s.q), T);
      reached += (s.status == IkStatus::kSolved || s.status == IkStatus::kSingular) && e.head<3>().norm() <= 1e-9 &&
                 e.tail<3>().norm() <= 1e-9 && InsideLimits(robot, s.q);
    }
    EXPECT_GE(reached, kTargets * 999 / 1000) << robot.dof() << " joints";
  }
}

// The numeric solver alone (closed form off) at structured configurations of two closed-form arms:
// singular poses, where a fixed damping stalled 1e-7 m short from every start. Every pose is reached.
TEST(NominalIk, NumericSolverDoesNotStallAtSingularConfigurations) {
  NominalIkOptions options;
  options.use_closed_form = false;
  for (const char* file : {"seed_nominal.yaml", "puma560_dh.yaml"}) {
    const Robot robot = LoadExampleRobot(file);
    const NominalInverseKinematics ik(robot, options);
    Rng rng(41);
    for (int trial = 0; trial < 150; ++trial) {
      const Eigen::VectorXd q = GridConfiguration(robot, M_PI / 4, &rng);
      const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
      const IkSolution s = ik.Solve(T, Eigen::VectorXd());
      EXPECT_FALSE(s.closed_form);
      EXPECT_TRUE(s.status == IkStatus::kSolved || s.status == IkStatus::kSingular)
          << file << " " << ToString(s.status) << " at " << (q * 180 / M_PI).transpose();
    }
  }
  // One descent (no restarts) from random starts, at the seed's arm stretched with its wrist singular:
  // the damped Newton it replaced ended 1e-7 m short from each of these starts after its 100 iterations.
  const Robot robot = LoadExampleRobot("seed_nominal.yaml");
  Eigen::VectorXd q(6);
  q << 0, -M_PI / 2, 0, -M_PI / 2, -M_PI / 2, 0;
  const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
  InverseKinematicsOptions one;
  one.restarts = 0;
  Rng rng(5);
  int converged = 0;
  for (int start = 0; start < 10; ++start) {
    const InverseKinematicsResult r = SolveInverseKinematics(robot, T, true, RandomConfiguration(robot, &rng), one);
    converged += r.converged;
    if (r.converged) {
      EXPECT_LE(PoseError(robot.model().ForwardKinematics(r.q), T).norm(), 1e-9);
    }
  }
  EXPECT_GE(converged, 5);
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
  const IkSolution o =
      NominalInverseKinematics(narrow, options).Solve(narrow.model().ForwardKinematics(q), Eigen::VectorXd());
  EXPECT_EQ(o.status, IkStatus::kOutOfLimits) << ToString(o.status);
  EXPECT_TRUE(o.q.allFinite());
}

// The status rule: a pose that no configuration reaches is unreachable, with the least-error joints,
// although that configuration (the arm stretched towards it) is singular; `singular` is for poses
// reached at a singular configuration.
TEST(NominalIk, UnreachedPoseIsUnreachableEvenWhereTheNearestConfigurationIsSingular) {
  for (const bool closed_form : {true, false}) {
    const Robot robot = LoadExampleRobot("seed_nominal.yaml");
    NominalIkOptions options;
    options.use_closed_form = closed_form;
    options.numeric.restarts = 5;
    const NominalInverseKinematics ik(robot, options);
    Eigen::VectorXd stretched(6);
    stretched << 0.3, -M_PI / 2, 0, -M_PI / 2, -M_PI / 2, 0;  // shoulder to wrist in one line
    Eigen::Isometry3d T = robot.model().ForwardKinematics(stretched);
    T.translation() *= 1.02;  // a little further out
    const IkSolution s = ik.Solve(T, Eigen::VectorXd());
    EXPECT_EQ(s.status, IkStatus::kUnreachable) << ToString(s.status);
    ASSERT_TRUE(s.q.allFinite());
    EXPECT_GT(s.position_error, 1e-3);
    EXPECT_NEAR(s.position_error, (robot.model().ForwardKinematics(s.q).translation() - T.translation()).norm(), 1e-12);
    EXPECT_LT(SigmaRatio(robot, s.q), 1e-6);  // the nearest configuration: stretched, singular
  }
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
