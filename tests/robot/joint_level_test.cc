// The joint level of robots: robot-file keys velocity_limits, coupling, gravity and
// joint_errors (round trips, messages), the measurement sequence of datasets (previous poses, from_q
// columns, subsets), readings -> actual angles and back, and the simulator with a truth that has them.
#include <cstring>

#include <gtest/gtest.h>

#include "robot/joint_readings.h"
#include "robot/prediction.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

const char* kJointLevel = R"(name: seed_real
convention: mdh
units: {length: mm, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 247.5, theta: 90, d: 0}
  - {alpha: 90, a: 0, theta: 0, d: 289.5}
  - {alpha: -90, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 0, theta: 0, d: 335.5}
  - {alpha: -90, a: 0, theta: 0, d: 0}
drives:
  ratio: [7946.45, 7946.45, 4782.59, 5150.48, 3973.22, 4138.78]
  counts_per_rev: [2048, 2048, 2048, 2048, 2048, 2048]
limits: [[-170, 170], [-30, 210], [-150, 150], [-180, 180], [-120, 120], [-360, 360]]
velocity_limits: [250, 250, 250, 320, 320, 420]
coupling: [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 1, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]
gravity: [0.01, 0, -1]
joint_errors:
  - {joint: 2, type: gravity, coefficients: {link2_x: 0.012, link2_y: -0.003, link3: 1.5e-05, link3_x: 0.004, link3_y: 0, link3_z: 0.0021, link4: 0, link4_x: 0, link4_y: 0, link4_z: 0, link5: 0, link5_x: 0, link5_y: 0, link5_z: 0, link6: 0, link6_x: 0, link6_y: 0, link6_z: 0}}
  - {joint: 3, type: gravity}
  - {joint: 1, type: harmonic, orders: [1, 2], coefficients: {sin1: 0.01, cos1: -0.004, sin2: 0.002, cos2: 0.001}}
  - {joint: 1, type: backlash, coefficients: {sign: 0.003}}
  - {joint: 1, type: approach, coefficients: {speed: 0.00028}}
  - {joint: 5, type: approach}
base: {xyz: [0, 0, 0], rpy: [0, 0, 0]}
tool: {xyz: [40, 30, 100], rpy: [0, 0, 0]}
)";

TEST(JointLevel, RobotFileWritesBackToItsOwnText) {
  const Robot robot = ParseRobotYaml(kJointLevel, "seed_real.yaml");
  EXPECT_EQ(RobotToYaml(robot), kJointLevel);
  ASSERT_EQ(robot.joint_errors.terms.size(), 6u);
  EXPECT_EQ(robot.joint_errors.terms[0].keys.size(), 18u);
  EXPECT_DOUBLE_EQ(robot.joint_errors.terms[0].coefficients[2], 1.5e-05 * (M_PI / 180) / 1e-3);  // deg/mm -> rad/m
  EXPECT_DOUBLE_EQ(robot.joint_errors.terms[4].coefficients[0], 0.00028);                        // seconds
  EXPECT_DOUBLE_EQ(robot.velocity_limits[5], 420 * M_PI / 180);
  EXPECT_EQ(robot.coupling(2, 1), 1.0);
  EXPECT_NEAR((robot.GravityDirection() - Eigen::Vector3d(0.01, 0, -1).normalized()).norm(), 0.0, 1e-16);
}

TEST(JointLevel, RandomCoefficientsKeepEveryBitInEveryUnit) {
  Robot robot = ParseRobotYaml(kJointLevel, "seed_real.yaml");
  Rng rng(17);
  for (const char* units : {"{length: mm, angle: deg}", "{length: m, angle: rad}", "{length: um, angle: deg}"}) {
    Eigen::VectorXd c(robot.joint_errors.num_coefficients());
    for (int k = 0; k < c.size(); ++k) c[k] = rng.Uniform(-1e-2, 1e-2);
    robot.joint_errors.SetCoefficients(c);
    std::string text = RobotToYaml(robot);
    text.replace(text.find("{length: mm, angle: deg}"), 24, units);
    const Robot once = ParseRobotYaml(text, "a.yaml");
    const Robot twice = ParseRobotYaml(RobotToYaml(once), "b.yaml");
    const Eigen::VectorXd a = once.joint_errors.Coefficients(), b = twice.joint_errors.Coefficients();
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0) << units;
  }
}

struct BadJointLevelCase {
  std::string label, replace, with, message;
};
void PrintTo(const BadJointLevelCase& c, std::ostream* os) { *os << c.label; }
class BadJointLevel : public ::testing::TestWithParam<BadJointLevelCase> {};

TEST_P(BadJointLevel, NamesFileLineColumnAndReason) {
  std::string text = kJointLevel;
  const size_t at = text.find(GetParam().replace);
  ASSERT_NE(at, std::string::npos) << GetParam().replace;
  text.replace(at, GetParam().replace.size(), GetParam().with);
  try {
    ParseRobotYaml(text, "bad.yaml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(GetParam().message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadJointLevel,
    ::testing::Values(
        BadJointLevelCase{"unknown_type", "type: backlash", "type: wobble",
                          "bad.yaml:22:22: unknown joint error type 'wobble'"},
        BadJointLevelCase{"joint_out_of_range", "{joint: 5, type: approach}", "{joint: 7, type: approach}",
                          "expected a joint 1..6"},
        BadJointLevelCase{"unknown_coefficient", "sign: 0.003", "sine: 0.003", "unknown coefficient 'sine'"},
        BadJointLevelCase{"left_out_term", "link2_x: 0.012", "link2: 0.012", "unknown coefficient 'link2'"},
        BadJointLevelCase{"orders_on_backlash", "type: backlash,", "type: backlash, orders: [1],",
                          "only harmonic terms take 'orders'"},
        BadJointLevelCase{"no_orders", "type: harmonic, orders: [1, 2],", "type: harmonic,", "lists no orders"},
        BadJointLevelCase{"velocity_count", "[250, 250, 250, 320, 320, 420]", "[250, 250]",
                          "expected 6 numbers for velocity_limits"},
        BadJointLevelCase{"velocity_zero", "[250, 250, 250, 320, 320, 420]", "[250, 250, 0, 320, 320, 420]",
                          "positive velocity limit"},
        BadJointLevelCase{"coupling_rows", "[0, 1, 1, 0, 0, 0], ", "", "expected 'coupling' to list 6 rows"},
        BadJointLevelCase{"coupling_singular", "[0, 1, 1, 0, 0, 0]", "[0, 1, 0, 0, 0, 0]",
                          "coupling: the matrix is singular"},
        BadJointLevelCase{"gravity_zero", "gravity: [0.01, 0, -1]", "gravity: [0, 0, 0]", "non-zero gravity"},
        BadJointLevelCase{"repeated_term", "{joint: 3, type: gravity}", "{joint: 2, type: gravity}", "given twice"},
        BadJointLevelCase{"approach_without_limits", "velocity_limits: [250, 250, 250, 320, 320, 420]\n", "",
                          "approach terms need velocity_limits"}),
    [](const auto& info) { return info.param.label; });

Dataset Rows(const std::vector<std::vector<double>>& qs) {
  Dataset d;
  d.dof = static_cast<int>(qs.front().size());
  for (const auto& q : qs) {
    Measurement m;
    m.q = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size()));
    d.rows.push_back(m);
  }
  return d;
}

TEST(MeasurementSequence, PreviousPoseIsTheLastRowWithOtherJoints) {
  Dataset d = Rows({{0, 0}, {1, 0}, {1, 0}, {1, 0}, {2, 0}, {2, 0}});
  const auto p = d.PreviousPoses();
  EXPECT_EQ(p[0].row, -1);
  EXPECT_EQ(p[1].row, 0);
  EXPECT_EQ(p[2].row, 0);  // three markers at one pose share the move that led there
  EXPECT_EQ(p[3].row, 0);
  EXPECT_EQ(p[4].row, 3);
  EXPECT_EQ(p[5].row, 3);
  d.rows[4].from_q = Eigen::Vector2d(5, 5);
  const auto q = d.PreviousPoses();
  EXPECT_TRUE(q[4].from_columns);
  EXPECT_EQ(*d.PreviousQ(q[5]), Eigen::Vector2d(5, 5));
}

TEST(MeasurementSequence, SubsetsRememberThePoseBeforeEachRow) {
  Dataset d = Rows({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
  d.rows[1].split = d.rows[3].split = Split::kTest;
  const Dataset test = d.Subset(Split::kTest);
  ASSERT_EQ(test.rows.size(), 2u);
  EXPECT_EQ(*test.rows[0].from_q, Eigen::Vector2d(0, 0));
  EXPECT_EQ(*test.rows[1].from_q, Eigen::Vector2d(2, 0));
  // ... and write them to from_q columns that read back the same.
  const Dataset back = ParseDatasetCsv(DatasetToCsv(test), "t.csv");
  EXPECT_NE(DatasetToCsv(test).find("from_q1_deg,from_q2_deg"), std::string::npos);
  EXPECT_EQ(*back.rows[1].from_q, *test.rows[1].from_q);
}

TEST(MeasurementSequence, FromColumnsAreAllOrNothingPerRow) {
  const std::string header = "q1_deg,q2_deg,x_mm,y_mm,z_mm,from_q1_deg,from_q2_deg\n";
  EXPECT_NO_THROW(ParseDatasetCsv(header + "1,2,0,0,0,,\n1,2,0,0,0,3,4\n", "f.csv"));
  try {
    ParseDatasetCsv(header + "1,2,0,0,0,3,\n", "f.csv");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f.csv:2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseDatasetCsv("q1_deg,q2_deg,x_mm,y_mm,z_mm,from_q1_deg\n1,2,0,0,0,3\n", "f.csv"),
               std::invalid_argument);
}

TEST(JointReadings, CouplingComesBeforeTheRatios) {
  Robot nominal = ParseRobotYaml(kJointLevel, "r.yaml");
  nominal.joint_errors = JointErrors();
  Robot real = nominal;
  real.drives->ratio[2] *= 1.01;
  const Eigen::VectorXd r = (Eigen::VectorXd(6) << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6).finished();
  const Eigen::VectorXd q = DriveAngles(nominal, real, r);
  EXPECT_DOUBLE_EQ(q[2], (0.2 + 0.3) / 1.01);
  EXPECT_DOUBLE_EQ(q[1], 0.2);
}

TEST(JointReadings, CommandsInvertTheWholeJointLevel) {
  const Robot nominal = testing::SeedNominal();
  Robot real = ParseRobotYaml(kJointLevel, "r.yaml");
  Rng rng(2);
  Eigen::VectorXd c = real.joint_errors.Coefficients();
  for (int k = 0; k < c.size(); ++k) c[k] += rng.Uniform(-2e-3, 2e-3);
  real.joint_errors.SetCoefficients(c);
  Eigen::VectorXd previous(6);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = rng.Uniform(-1.5, 1.5);
    const Eigen::VectorXd* from = trial ? &previous : nullptr;
    double residual = 1;
    const Eigen::VectorXd command = ReadingsFromActual(nominal, real, q, from, &residual);
    EXPECT_LT(residual, 1e-14);
    EXPECT_LT((ActualFromReadings(nominal, real, command, from) - q).cwiseAbs().maxCoeff(), 1e-13) << trial;
    previous = command;
  }
}

TEST(JointLevelSimulation, NoiseFreeRowsAreTheTruthAfterTheMoveThatLedThere) {
  const Robot nominal = testing::SeedNominal();
  Robot truth = ParseRobotYaml(kJointLevel, "truth.yaml");
  SimulatorOptions o;
  o.protocol = "random";
  o.poses = 30;
  o.seed = 4;
  const Dataset data = Simulate(nominal, truth, o);
  const auto previous = data.PreviousPoses();
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Eigen::VectorXd qbar = DriveAngles(nominal, truth, data.rows[i]);
    Eigen::VectorXd expected = qbar;
    if (i > 0) {
      const Eigen::VectorXd prev = DriveAngles(nominal, truth, data.rows[i - 1]);
      expected = ApplyJointErrors(truth, qbar, &prev);
    } else {
      expected = ApplyJointErrors(truth, qbar, nullptr);
    }
    const Eigen::Vector3d p = truth.model().ForwardKinematics(expected).translation();
    EXPECT_LT((p - data.rows[i].p).norm(), 1e-15) << i;
    EXPECT_LT((PredictMarker(nominal, truth, data, i, previous) - data.rows[i].p).norm(), 1e-15) << i;
  }
  // The joint errors matter: the same truth without them misses by far more than rounding.
  Robot plain = truth;
  plain.joint_errors = JointErrors();
  EXPECT_GT(EvaluatePredictions(nominal, plain, data).position_stats.rms, 1e-4);
  EXPECT_LT(EvaluatePredictions(nominal, truth, data).position_stats.max, 1e-15);
}

}  // namespace
}  // namespace kincal
