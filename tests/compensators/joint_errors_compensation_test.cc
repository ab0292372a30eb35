// Compensation with joint-level errors: the commands a compensator writes must put the real arm (the
// identified robot, with coupling, ratios and joint errors) on each target of a program (CompensateProgram),
// each target reached from the commands of the one before or from the pose the target names, so that
// move-dependent errors (backlash, approach) are inverted for the move the arm actually makes.
#include <gtest/gtest.h>

#include "compensators/compensator.h"
#include "compensators/program.h"
#include "robot/joint_readings.h"
#include "framework/random.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

using T = JointErrorTerm::Type;

Robot RealArm() {
  Robot robot = SeedTruth();
  robot.velocity_limits = Eigen::VectorXd::Constant(6, 3.0);
  const auto term = [](T type, int joint, std::vector<int> orders = {}) {
    JointErrorTerm t;
    t.type = type;
    t.joint = joint;
    t.orders = std::move(orders);
    return t;
  };
  robot.joint_errors.terms = {term(T::kGravity, 1),  term(T::kGravity, 2),  term(T::kHarmonic, 0, {1, 2}),
                              term(T::kBacklash, 0), term(T::kBacklash, 3), term(T::kApproach, 1),
                              term(T::kApproach, 4)};
  robot.joint_errors.Bind(robot.model());
  Rng rng(12);
  Eigen::VectorXd c(robot.joint_errors.num_coefficients());
  for (int k = 0; k < c.size(); ++k) c[k] = rng.Uniform(-1e-3, 1e-3);
  robot.joint_errors.SetCoefficients(c);
  return robot;
}

class JointErrorCompensation : public ::testing::TestWithParam<std::string> {};

TEST_P(JointErrorCompensation, TheRealArmReachesEveryTargetOfAProgram) {
  const Robot nominal = SeedNominal();
  const Robot real = RealArm();
  auto compensator = Compensators().Create(GetParam(), YAML::Node());
  compensator->Prepare(nominal, real);
  Rng rng(4);
  Robot geometric_only = real;  // the same arm as a compensator blind to joint errors sees it
  geometric_only.joint_errors = JointErrors();
  std::vector<CompensationTarget> program;
  for (int t = 0; t < 40; ++t) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-1.2, 1.2);
    q[4] = rng.Uniform(0.3, 1.2);  // away from the wrist singularity
    CompensationTarget target;
    target.T_meas_tool = real.model().ForwardKinematics(q);
    target.seed = q;
    program.push_back(target);
  }
  // Target 20 comes from a pose of its own (a targets file's from_q): the arm makes that move instead.
  const Eigen::VectorXd from_elsewhere = Eigen::VectorXd::Constant(6, 0.4);
  program[20].previous_command = from_elsewhere;
  const std::vector<CompensationResult> results = CompensateProgram(*compensator, program);
  ASSERT_EQ(results.size(), program.size());
  double worst = 0.0, worst_blind = 0.0;
  for (size_t t = 0; t < program.size(); ++t) {
    const CompensationTarget& target = program[t];
    const CompensationResult& r = results[t];
    ASSERT_EQ(r.report.status, CompensationStatus::kConverged) << t << ": " << r.report.message;
    const Eigen::VectorXd* previous = t == 20 ? &from_elsewhere : t > 0 ? &results[t - 1].q_command : nullptr;
    // Where the real arm goes on these commands, coming from the previous ones (commanded angles through
    // the nominal ratios, without the rounding to whole encoder counts).
    const Eigen::VectorXd q_real = ActualFromReadings(nominal, real, r.q_command, previous);
    const Eigen::Isometry3d reached = real.model().ForwardKinematics(q_real);
    worst = std::max(worst, (reached.translation() - target.T_meas_tool.translation()).norm());
    const Eigen::VectorXd blind = ReadingsFromActual(nominal, geometric_only, r.q_actual, nullptr);
    const Eigen::VectorXd q_blind = ActualFromReadings(nominal, real, blind, previous);
    worst_blind = std::max(
        worst_blind, (real.model().ForwardKinematics(q_blind).translation() - target.T_meas_tool.translation()).norm());
    EXPECT_LT(RotationAngleBetween(reached.linear(), target.T_meas_tool.linear()), 1e-8) << t;
  }
  EXPECT_LT(worst, 1e-9) << GetParam();
  // Without the inversion the commands miss by millimetres: the test would notice a missing inversion.
  EXPECT_GT(worst_blind, 1e-4);
  std::printf("%s: worst position error over the program %.3g m (%.3g m without inverting the joint errors)\n",
              GetParam().c_str(), worst, worst_blind);
}

INSTANTIATE_TEST_SUITE_P(Iterative, JointErrorCompensation, ::testing::Values("analytic_derivative", "jacobian"));

}  // namespace
}  // namespace kincal::testing
