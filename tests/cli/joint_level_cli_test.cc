// The command line with joint-level errors: `kincal predict` gives, row by row and in order,
// where the robot puts each measured point (the truth predicts its own noise-free data exactly); a
// compensated program reaches its targets on the real arm; bad input ends with exit 2 and one line.
#include <gtest/gtest.h>

#include "framework/csv.h"
#include "robot/joint_readings.h"
#include "framework/random.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;
using testing::TempDir;

// The seed's truth with joint errors of every kind, written as a robot file.
std::string WriteRealArm(const TempDir& dir) {
  Robot robot = testing::SeedTruth();
  std::string text = RobotToYaml(robot);
  text.insert(text.find("base:"),
              "velocity_limits: [250, 250, 250, 320, 320, 420]\n"
              "joint_errors:\n"
              "  - {joint: 2, type: gravity, coefficients: {link2_x: 0.02, link3_y: -0.01, link4_x: 0.005}}\n"
              "  - {joint: 1, type: harmonic, orders: [1], coefficients: {sin1: 0.01, cos1: -0.02}}\n"
              "  - {joint: 3, type: backlash, coefficients: {sign: 0.01}}\n"
              "  - {joint: 1, type: approach, coefficients: {speed: 0.0005}}\n");
  const std::string path = dir.path("real.yaml");
  testing::WriteText(path, text);
  return path;
}

TEST(JointLevelCli, PredictGivesEveryRowInOrder) {
  TempDir dir;
  const std::string real = WriteRealArm(dir);
  const std::string nominal = SourcePath("examples/robots/seed_nominal.yaml");
  auto r = RunKincal("simulate --nominal " + nominal + " --truth " + real +
                     " --protocol random --poses 25 --seed 3 --out " + dir.path("data.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunKincal("predict --robot " + real + " --nominal " + nominal + " --data " + dir.path("data.csv") + " --out " +
                dir.path("pred.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = ParseCsv(testing::ReadText(dir.path("pred.csv")), "pred.csv");
  ASSERT_EQ(t.rows.size(), 25u);
  EXPECT_EQ(t.header.cells, (std::vector<std::string>{"x_mm", "y_mm", "z_mm", "dx_mm", "dy_mm", "dz_mm", "error_mm"}));
  const Dataset data = ReadDataset(dir.path("data.csv"));
  for (size_t i = 0; i < t.rows.size(); ++i) {
    EXPECT_NEAR(std::stod(t.rows[i].cells[0]), data.rows[i].p.x() * 1e3, 1e-9);  // mm
    EXPECT_LT(std::stod(t.rows[i].cells[6]), 1e-9);
  }
  // The same arm without its joint errors predicts millimetres off.
  const Robot truth = ReadRobotFile(real);
  Robot plain = truth;
  plain.joint_errors = JointErrors();
  WriteRobotFile(plain, dir.path("plain.yaml"));
  r = RunKincal("predict --robot " + dir.path("plain.yaml") + " --nominal " + nominal + " --data " +
                dir.path("data.csv") + " --out " + dir.path("pred2.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("RMS error"), std::string::npos);
  const CsvTable t2 = ParseCsv(testing::ReadText(dir.path("pred2.csv")), "pred2.csv");
  double worst = 0;
  for (const auto& row : t2.rows) worst = std::max(worst, std::stod(row.cells[6]));
  EXPECT_GT(worst, 0.1);
}

TEST(JointLevelCli, PredictRejectsBadInputWithOneLine) {
  TempDir dir;
  const std::string robot = SourcePath("examples/robots/seed_nominal.yaml");
  testing::WriteText(dir.path("three.csv"), "q1_deg,q2_deg,q3_deg,x_mm,y_mm,z_mm\n1,2,3,4,5,6\n");
  auto r = RunKincal("predict --robot " + robot + " --data " + dir.path("three.csv") + " --out " + dir.path("p.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("three.csv:1:1:"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("p.csv")));
  testing::WriteText(dir.path("m.csv"),
                     "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,marker\n0,0,0,0,0,0,1,2,3,SMR9\n");
  r = RunKincal("predict --robot " + robot + " --data " + dir.path("m.csv") + " --out " + dir.path("p.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("m.csv:2: robot 'seed_nominal' has no marker 'SMR9'"), std::string::npos) << r.err;
  r = RunKincal("predict --robot " + dir.path("none.yaml") + " --data " + dir.path("m.csv") + " --out " +
                dir.path("p.csv"));
  EXPECT_EQ(r.exit_code, 2);
}

TEST(JointLevelCli, CompensateTakesTheTargetsAsAProgram) {
  TempDir dir;
  const std::string real = WriteRealArm(dir);
  const std::string nominal = SourcePath("examples/robots/seed_nominal.yaml");
  const Robot truth = ReadRobotFile(real), controller = ReadRobotFile(nominal);
  // Targets: poses of the real arm at random joints, with the controller's solution as seeds.
  std::string csv = "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  Rng rng(8);
  for (int t = 0; t < 12; ++t) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-1.0, 1.0);
    q[4] = rng.Uniform(0.4, 1.0);
    const Eigen::Isometry3d T = truth.model().ForwardKinematics(q);
    const Eigen::Quaterniond o(T.linear());
    for (int j = 0; j < 6; ++j) csv += FormatExact(q[j] * 180 / M_PI) + ",";
    for (int k = 0; k < 3; ++k) csv += FormatExact(T.translation()[k] * 1e3) + ",";
    csv += FormatExact(o.w()) + "," + FormatExact(o.x()) + "," + FormatExact(o.y()) + "," + FormatExact(o.z()) + "\n";
  }
  testing::WriteText(dir.path("targets.csv"), csv);
  auto r = RunKincal("compensate --nominal " + nominal + " --identified " + real + " --targets " +
                     dir.path("targets.csv") + " --method analytic_derivative --out " + dir.path("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Dataset targets = ReadDataset(dir.path("targets.csv"));
  const CsvTable out = ParseCsv(testing::ReadText(dir.path("q.csv")), "q.csv");
  ASSERT_EQ(out.rows.size(), 12u);
  Eigen::VectorXd previous;
  for (size_t t = 0; t < out.rows.size(); ++t) {
    Eigen::VectorXd command(6);
    for (int j = 0; j < 6; ++j) command[j] = std::stod(out.rows[t].cells[j]) * M_PI / 180;
    const Eigen::VectorXd q = ActualFromReadings(controller, truth, command, previous.size() ? &previous : nullptr);
    // The file holds the shortest decimals of the commands: the arm lands within rounding of the target.
    EXPECT_LT((truth.model().ForwardKinematics(q).translation() - targets.rows[t].p).norm(), 1e-9) << t;
    previous = command;
  }
}

}  // namespace
}  // namespace kincal
