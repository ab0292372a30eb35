// One fixture run by every registered compensator (Drake's optimization_examples style): the seed's arm,
// nominal (Table 1) for the controller and identified (Table 2) as the real arm, random reachable
// targets with the controller's nominal solutions as seeds. Invariants hold for every method; what each
// method promises about accuracy is listed in ExpectationFor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "robot/inverse_kinematics.h"
#include "framework/math.h"
#include "testing/compensator_conformance.h"
#include "tests/compensators/compensator_fixture.h"

namespace kincal {
namespace {

using testing::Arm;
using testing::Prepared;

struct Expectation {
  bool exact = false;             // reaches reachable, well-conditioned targets to the tolerances below
  double position = INFINITY;     // m
  double orientation = INFINITY;  // rad
  int max_iterations = 0;
  // Bound on the position error of lookups reporting kConverged (joint_space).
  double converged_position_bound = INFINITY;
};

Expectation ExpectationFor(const std::string& name) {
  Expectation e;
  if (name == "analytic_derivative" || name == "jacobian") {
    e.exact = true;
    e.position = 1e-12;     // 1e-9 mm
    e.orientation = 1e-12;  // rad
    e.max_iterations = 8;
  } else if (name == "joint_space") {
    // Two Jacobian steps on an exact expansion: kConverged means within its position_tolerance (1 um);
    // the acceptance figure over all targets is checked in joint_space_accuracy_test.
    e.converged_position_bound = 1e-6;
  }
  return e;  // none, and methods this suite does not know yet: the invariants only
}

// The squared residual each exact method decreases (position rows in units of 0.5 m, its default).
double MethodCost(const std::string& name, double position_error, double orientation_error) {
  const double p = position_error / 0.5;
  if (name == "analytic_derivative") return p * p + 8 * std::pow(std::sin(orientation_error / 2), 2);
  return p * p + orientation_error * orientation_error;
}

class CompensatorConformance : public ::testing::TestWithParam<std::string> {
 protected:
  const Compensator& compensator() const { return Prepared(GetParam()); }

  // What must hold for any result of any method (the installed kit, testing/compensator_conformance.h).
  void CheckInvariants(const CompensationTarget& target, const CompensationResult& r) const {
    // The same code computes both: the errors agree to rounding of a few ulp.
    EXPECT_TRUE(testing::CompensationResultIsConsistent(Arm().identified, target, r, 1e-15));
  }
};

TEST_P(CompensatorConformance, ReachesReachableTargets) {
  const Expectation expect = ExpectationFor(GetParam());
  const RandomTargets targets = testing::WellConditionedTargets(60, 11);
  std::vector<int> iterations;
  for (const CompensationTarget& target : targets.targets) {
    const CompensationResult r = compensator().Compensate(target);
    CheckInvariants(target, r);
    iterations.push_back(r.report.iterations);
    if (expect.exact) {
      EXPECT_EQ(r.report.status, CompensationStatus::kConverged) << r.report.message;
      EXPECT_LE(r.report.position_error, expect.position);
      EXPECT_LE(r.report.orientation_error, expect.orientation);
      EXPECT_LE(r.report.iterations, expect.max_iterations);
    }
    if (r.report.status == CompensationStatus::kConverged) {
      EXPECT_LE(r.report.position_error, expect.converged_position_bound);
    }
    if (GetParam() == "none") {  // the baseline commands the controller's solution unchanged
      EXPECT_LE((r.q_command - target.seed).cwiseAbs().maxCoeff(), 1e-15 * (1 + target.seed.cwiseAbs().maxCoeff()));
    }
  }
  std::sort(iterations.begin(), iterations.end());
  RecordProperty("median_iterations", iterations[iterations.size() / 2]);
  RecordProperty("max_iterations", iterations.back());
}

// q_command (through the nominal ratios) and the encoder counts describe the motion q_actual.
TEST_P(CompensatorConformance, CommandsAndCountsDescribeTheSameMotion) {
  const Robot& nominal = Arm().nominal;
  const Robot& identified = Arm().identified;
  const RandomTargets targets = testing::WellConditionedTargets(10, 12);
  for (const CompensationTarget& target : targets.targets) {
    const CompensationResult r = compensator().Compensate(target);
    const Eigen::VectorXd actual = DriveModel::ActualFromCommanded(*nominal.drives, *identified.drives, r.q_command);
    EXPECT_LE((actual - r.q_actual).cwiseAbs().maxCoeff(), 1e-14);
    ASSERT_EQ(r.encoders.size(), static_cast<size_t>(identified.dof()));
    EXPECT_EQ(r.encoders, nominal.drives->CommandCounts(r.q_command));
    // The real joint turns by the counts over its real ratio: q_actual, to within half a count.
    Eigen::VectorXd counts(identified.dof());
    for (int j = 0; j < identified.dof(); ++j) counts[j] = static_cast<double>(r.encoders[j]);
    const Eigen::VectorXd turned = identified.drives->AnglesFromCounts(counts);
    for (int j = 0; j < identified.dof(); ++j) {
      const double half_count = M_PI / (identified.drives->counts_per_rev[j] * identified.drives->ratio[j]);
      EXPECT_LE(std::abs(turned[j] - r.q_actual[j]), half_count * (1 + 1e-9));
    }
  }
}

TEST_P(CompensatorConformance, TargetOutOfReachGivesAStatusNotGarbage) {
  const Expectation expect = ExpectationFor(GetParam());
  const RandomTargets targets = testing::WellConditionedTargets(3, 13);
  for (CompensationTarget target : targets.targets) {
    target.T_meas_tool.translation() += Eigen::Vector3d(2.0, 1.0, 1.0);  // about 2.5 m beyond
    for (const bool with_seed : {true, false}) {
      CompensationTarget t = target;
      if (!with_seed) t.seed.resize(0);
      const CompensationResult r = compensator().Compensate(t);
      CheckInvariants(t, r);
      EXPECT_GT(r.report.position_error, 0.5);
      if (expect.exact) {
        EXPECT_EQ(r.report.status, CompensationStatus::kUnreachable)
            << r.report.message << " with seed " << with_seed << " pe " << r.report.position_error;
      }
    }
  }
}

// Elbow stretched (joint 4 at 0, axes 3 and 5 aligned) and joint 5 at 90 deg: the identified arm reaches
// these targets, but its Jacobian is nearly singular there and the nominal seed can be far off.
TEST_P(CompensatorConformance, NearSingularTargetsGiveAStatusNotGarbage) {
  const Expectation expect = ExpectationFor(GetParam());
  const double deg = M_PI / 180;
  Eigen::VectorXd elbow(6), wrist(6);
  elbow << 20, 30, 40, 0, 45, 10;
  wrist << 20, 30, 40, 60, 89.9, 10;
  for (const Eigen::VectorXd& q : {Eigen::VectorXd(elbow * deg), Eigen::VectorXd(wrist * deg)}) {
    CompensationTarget target;
    target.T_meas_tool = Arm().identified.model().ForwardKinematics(q);
    InverseKinematicsOptions ik;
    ik.restarts = 0;
    target.seed = SolveInverseKinematics(Arm().nominal, target.T_meas_tool, true, q, ik).q;
    const CompensationResult r = compensator().Compensate(target);
    CheckInvariants(target, r);
    if (!expect.exact) continue;
    EXPECT_TRUE(r.report.status == CompensationStatus::kConverged || r.report.status == CompensationStatus::kSingular)
        << ToString(r.report.status);
    if (r.report.status == CompensationStatus::kConverged) {
      EXPECT_LE(r.report.position_error, expect.position);
      EXPECT_LE(r.report.orientation_error, expect.orientation);
    }
    // Never worse than where it started: the seed, commanded as actual angles.
    const Vector6d e0 = PoseError(Arm().identified.model().ForwardKinematics(target.seed), target.T_meas_tool);
    EXPECT_LE(MethodCost(GetParam(), r.report.position_error, r.report.orientation_error),
              MethodCost(GetParam(), e0.head<3>().norm(), e0.tail<3>().norm()));
  }
}

TEST_P(CompensatorConformance, TargetsWithoutSeedsUseTheNominalInverseKinematics) {
  const Expectation expect = ExpectationFor(GetParam());
  const RandomTargets targets = testing::WellConditionedTargets(5, 14);
  for (CompensationTarget target : targets.targets) {
    target.seed.resize(0);
    const CompensationResult r = compensator().Compensate(target);
    CheckInvariants(target, r);
    EXPECT_TRUE(r.report.seed_computed);
    if (expect.exact) {
      EXPECT_EQ(r.report.status, CompensationStatus::kConverged) << r.report.message;
      EXPECT_LE(r.report.position_error, expect.position);
      EXPECT_LE(r.report.orientation_error, expect.orientation);
    }
  }
}

TEST_P(CompensatorConformance, PositionOnlyTargets) {
  const Expectation expect = ExpectationFor(GetParam());
  const RandomTargets targets = testing::WellConditionedTargets(10, 15, /*orientation=*/false);
  for (const CompensationTarget& target : targets.targets) {
    ASSERT_FALSE(target.has_orientation);
    const CompensationResult r = compensator().Compensate(target);
    CheckInvariants(target, r);
    EXPECT_EQ(r.report.orientation_error, 0.0);
    if (expect.exact) {
      EXPECT_EQ(r.report.status, CompensationStatus::kConverged) << r.report.message;
      EXPECT_LE(r.report.position_error, expect.position);
    }
  }
}

std::string Name(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

INSTANTIATE_TEST_SUITE_P(AllCompensators, CompensatorConformance, ::testing::ValuesIn(Compensators().RegisteredNames()),
                         Name);

TEST(Compensators, EveryMethodOfTheIssueIsRegistered) {
  for (const char* name : {"none", "analytic_derivative", "jacobian", "joint_space"}) {
    EXPECT_TRUE(Compensators().IsRegistered(name)) << name;
  }
}

}  // namespace
}  // namespace kincal
