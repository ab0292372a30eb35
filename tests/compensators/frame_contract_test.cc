// The frame contract (compensators/compensator.h): targets in the measurement frame, the controller the
// nominal geometry placed by the identified robot's base and tool. Every registered compensator, with and
// without seeds, on the seed's arm as a tracker sees it: nominal file with base and tool identity (as
// nominal files are), identified robot 1.5 m from the tracker and turned 90 deg about z, tool 120 mm off
// the flange; seeds are the controller's solutions (its geometry placed by that base and tool).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "compensators/common/random_targets.h"
#include "compensators/compensator.h"
#include "framework/math.h"
#include "framework/random.h"
#include "robot/nominal_ik.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

struct FarBaseArm {
  Robot nominal = testing::SeedNominal();
  Robot identified = testing::SeedTruth();
  Robot controller;
  RandomTargets targets;
  FarBaseArm() {
    nominal.model().SetBase(Eigen::Isometry3d::Identity());
    nominal.model().SetTool(Eigen::Isometry3d::Identity());
    identified.model().SetBase(PoseFromXyzRpy({1.2, 0.9, 0.1}, {0.0, 0.0, M_PI / 2}));  // 1.5 m, 90 deg about z
    identified.model().SetTool(PoseFromXyzRpy({0.04, 0.03, 0.11}, {0.0, 0.2, 0.0}));    // 121 mm
    controller = ControllerRobot(nominal, identified);
    RandomTargetOptions o;
    o.count = 2000;
    o.seed = 2020;
    targets = MakeRandomTargets(controller, identified, o);
  }
};

const FarBaseArm& Far() {
  static const FarBaseArm arm;
  return arm;
}

const Compensator& PreparedFar(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Compensator>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = Compensators().Create(name, YAML::Load("{}"));
    slot->Prepare(Far().nominal, Far().identified);
  }
  return *slot;
}

bool Within(const CompensationResult& r, double position, double orientation) {
  return r.report.position_error <= position && r.report.orientation_error <= orientation;
}

TEST(FrameContract, TheControllerIsTheNominalGeometryPlacedByTheIdentifiedBaseAndTool) {
  const Robot& nominal = Far().nominal;
  const Robot& identified = Far().identified;
  const Robot& controller = Far().controller;
  Rng rng(5);
  for (int k = 0; k < 20; ++k) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-2.0, 2.0);
    const Eigen::Isometry3d expected =
        identified.model().base() * nominal.model().ForwardKinematics(q) * identified.model().tool();
    EXPECT_LE((controller.model().ForwardKinematics(q).matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-14);
  }
  // A nominal file that gives its own base or tool keeps it (the cell's work object or tool data).
  Robot own = nominal;
  const Eigen::Isometry3d T_meas_base = PoseFromXyzRpy({0.5, -0.2, 0.0}, {0.0, 0.0, 0.3});
  own.model().SetBase(T_meas_base);
  const Robot mixed = ControllerRobot(own, identified);
  EXPECT_TRUE(mixed.model().base().isApprox(T_meas_base, 1e-15));
  EXPECT_TRUE(mixed.model().tool().isApprox(identified.model().tool(), 1e-15));
  // Targets in the base frame are moved by the controller's base.
  const Eigen::Isometry3d T_base_tool = PoseFromXyzRpy({0.3, 0.1, 0.4}, {0.1, 0.2, 0.3});
  EXPECT_TRUE(TargetFromBaseFrame(controller, T_base_tool).isApprox(identified.model().base() * T_base_tool, 1e-15));
}

class FarBase : public ::testing::TestWithParam<std::string> {};

// Every compensator, with the controller's seeds and without: the exact methods reach every target, the
// baseline commands the seed (which the controller's own inverse kinematics reproduces without one),
// joint_space reaches at least 95 % within 0.05 mm and 1e-4 rad.
TEST_P(FarBase, EveryCompensatorWithAndWithoutSeeds) {
  const std::string& name = GetParam();
  const Compensator& c = PreparedFar(name);
  const NominalInverseKinematics controller_ik(Far().controller);
  const int count = 300;
  for (const bool with_seed : {true, false}) {
    int within = 0, on_branch = 0;
    for (int i = 0; i < count; ++i) {
      CompensationTarget target = Far().targets.targets[i];
      if (!with_seed) target.seed.resize(0);
      const CompensationResult r = c.Compensate(target);
      ASSERT_TRUE(r.q_actual.allFinite());
      within += Within(r, 0.05e-3, 1e-4);
      // Seedless: the controller's own solution, nearest the middle of the limits.
      const Eigen::VectorXd seed =
          with_seed ? Eigen::VectorXd(target.seed) : controller_ik.Solve(target.T_meas_tool, Eigen::VectorXd()).q;
      on_branch += (r.q_actual - seed).cwiseAbs().maxCoeff() <= 0.5;
      if (name == "analytic_derivative" || name == "jacobian") {
        EXPECT_EQ(r.report.status, CompensationStatus::kConverged) << i << " " << r.report.message;
        EXPECT_LE(r.report.position_error, 1e-9);
        EXPECT_LE(r.report.orientation_error, 1e-9);
      } else if (name == "none") {
        // The controller's solution for the target: a far base does not move it.
        const Eigen::Isometry3d T_controller = Far().controller.model().ForwardKinematics(r.q_command);
        EXPECT_LE(PoseError(T_controller, target.T_meas_tool).norm(), 1e-9) << i;
      }
    }
    RecordProperty(name + (with_seed ? "_within_seeds" : "_within_no_seeds"), within);
    if (name == "joint_space") {
      EXPECT_GE(within, 0.95 * count) << "with seed " << with_seed;
    }
    if (name == "analytic_derivative" || name == "jacobian") {
      EXPECT_GE(on_branch, count - 3) << "with seed " << with_seed;
    }
  }
}

std::string Name(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

INSTANTIATE_TEST_SUITE_P(AllCompensators, FarBase, ::testing::ValuesIn(Compensators().RegisteredNames()), Name);

// The required figures on all 2000 targets: joint_space within 0.05 mm and 1e-4 rad with seeds; the
// analytic derivative without seeds on the controller's branch, and its time against the seeded run.
TEST(FarBaseFigures, JointSpaceAndSeedlessAnalyticDerivative) {
  const std::vector<CompensationTarget>& targets = Far().targets.targets;
  const Compensator& js = PreparedFar("joint_space");
  int within = 0;
  for (const CompensationTarget& t : targets) within += Within(js.Compensate(t), 0.05e-3, 1e-4);
  const double js_fraction = within / double(targets.size());
  EXPECT_GE(js_fraction, 0.95);

  const Compensator& ad = PreparedFar("analytic_derivative");
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  for (const CompensationTarget& t : targets) ad.Compensate(t);
  const auto t1 = Clock::now();
  std::vector<CompensationResult> seedless;
  seedless.reserve(targets.size());
  for (const CompensationTarget& t : targets) {
    CompensationTarget target = t;
    target.seed.resize(0);
    seedless.push_back(ad.Compensate(target));
  }
  const auto t2 = Clock::now();
  // On the controller's branch: converged from its solution or from a start within same_branch_distance
  // of it (not branch_changed). Where the run left that branch, a search of 3000 random starts around the
  // controller's solution that keeps to the branch says whether the identified arm reaches the target
  // there at all.
  const auto exhaustive = Compensators().Create(
      "analytic_derivative", YAML::Load("{other_branches: false, random_starts: 3000, max_iterations: 100}"));
  exhaustive->Prepare(Far().nominal, Far().identified);
  int reached = 0, on_branch = 0, branch_exists = 0;
  for (size_t i = 0; i < targets.size(); ++i) {
    const CompensationResult& r = seedless[i];
    reached += r.report.status == CompensationStatus::kConverged;
    const bool ok = r.report.status == CompensationStatus::kConverged && !r.report.branch_changed;
    on_branch += ok;
    if (ok) {
      ++branch_exists;
      continue;
    }
    CompensationTarget target = targets[i];
    target.seed.resize(0);
    branch_exists += exhaustive->Compensate(target).report.status == CompensationStatus::kConverged;
  }
  const double with_seeds = std::chrono::duration<double>(t1 - t0).count();
  const double without = std::chrono::duration<double>(t2 - t1).count();
  const double fraction = on_branch / double(branch_exists);
  std::printf(
      "far base: joint_space %.2f %% within 0.05 mm and 1e-4 rad; analytic_derivative without seeds: "
      "%d reached, %d on the controller's branch of %d where it exists (%.2f %%); %.3f s against %.3f s "
      "with seeds (%.2fx)\n",
      100 * js_fraction, reached, on_branch, branch_exists, 100 * fraction, without, with_seeds, without / with_seeds);
  EXPECT_GE(fraction, 0.999);
  EXPECT_GE(reached, 0.999 * targets.size());
}

}  // namespace
}  // namespace kincal
