// `kincal compensate` end to end: targets in, joints and motor counts out, in order, every number finite;
// bad input gives exit status 2, one line on stderr and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "framework/csv.h"
#include "framework/math.h"
#include "framework/units.h"
#include "tests/compensators/compensator_fixture.h"

namespace kincal {
namespace {

using testing::Arm;
using testing::RunKincal;
using testing::TempDir;

std::string Robots() {
  const std::string dir = testing::SourcePath("examples/robots/");
  return " --nominal " + dir + "seed_nominal.yaml --identified " + dir + "seed_identified.yaml";
}

// Targets as a CSV: position in mm or m, optionally the orientation and the seeds in deg or rad.
std::string TargetsCsv(const RandomTargets& targets, bool metres, bool orientation, bool seeds, bool radians) {
  std::ostringstream out;
  out.precision(17);
  const std::string l = metres ? "_m" : "_mm";
  out << "# targets for kincal compensate\nx" << l << ",y" << l << ",z" << l;
  if (orientation) out << ",qw,qx,qy,qz";
  if (seeds)
    for (int j = 1; j <= 6; ++j) out << ",q" << j << (radians ? "_rad" : "_deg");
  out << "\n";
  for (const CompensationTarget& t : targets.targets) {
    const Eigen::Vector3d p = t.T_meas_tool.translation() * (metres ? 1.0 : 1e3);
    out << p.x() << "," << p.y() << "," << p.z();
    if (orientation) {
      const Eigen::Quaterniond quat(t.T_meas_tool.linear());
      out << "," << quat.w() << "," << quat.x() << "," << quat.y() << "," << quat.z();
    }
    if (seeds)
      for (int j = 0; j < 6; ++j) out << "," << t.seed[j] * (radians ? 1.0 : 180 / M_PI);
    out << "\n";
  }
  return out.str();
}

double Number(const CsvTable& t, const CsvRow& row, const std::string& column) {
  const int c = FindColumn(t, column);
  EXPECT_GE(c, 0) << column;
  double v = NAN;
  EXPECT_TRUE(ParseDouble(row.cells.at(c), &v)) << column << " = '" << row.cells.at(c) << "'";
  return v;
}

// Runs the command and checks every row against the identified robot: commanded joints converted with
// the nominal ratios reach the target; counts are the nominal controller's counts of those joints.
void CheckCompensation(const std::string& method, const RandomTargets& targets, bool metres, bool orientation,
                       bool seeds, bool radians) {
  TempDir dir;
  testing::WriteText(dir.path("t.csv"), TargetsCsv(targets, metres, orientation, seeds, radians));
  const auto run = RunKincal("compensate" + Robots() + " --targets " + dir.path("t.csv") + " --method " + method +
                             " --out " + dir.path("j.csv"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable out = ParseCsv(testing::ReadText(dir.path("j.csv")), "j.csv");
  ASSERT_EQ(out.rows.size(), targets.targets.size());
  const std::string angle = seeds && radians ? "_rad" : "_deg";
  const double to_rad = seeds && radians ? 1.0 : M_PI / 180;
  const std::string length = metres ? "m" : "mm";
  for (size_t i = 0; i < out.rows.size(); ++i) {
    const CsvRow& row = out.rows[i];
    for (const std::string& cell : row.cells) EXPECT_EQ(cell.find("nan"), std::string::npos);
    Eigen::VectorXd q_command(6);
    std::vector<int64_t> counts;
    for (int j = 0; j < 6; ++j) {
      q_command[j] = Number(out, row, "q" + std::to_string(j + 1) + angle) * to_rad;
      counts.push_back(static_cast<int64_t>(Number(out, row, "enc" + std::to_string(j + 1))));
    }
    EXPECT_EQ(row.cells[FindColumn(out, "status")], "converged");
    EXPECT_EQ(Number(out, row, "seed_computed"), seeds ? 0.0 : 1.0);
    EXPECT_GE(Number(out, row, "iterations"), 1.0);
    EXPECT_LE(Number(out, row, "position_error_" + length), metres ? 1e-12 : 1e-9);
    EXPECT_LE(Number(out, row, "orientation_error_deg"), orientation ? 1e-12 * 180 / M_PI : 0.0);
    EXPECT_EQ(counts, Arm().nominal.drives->CommandCounts(q_command));
    const Eigen::VectorXd q_actual =
        DriveModel::ActualFromCommanded(*Arm().nominal.drives, *Arm().identified.drives, q_command);
    const Vector6d e = PoseError(Arm().identified.model().ForwardKinematics(q_actual), targets.targets[i].T_meas_tool);
    EXPECT_LE(e.head<3>().norm(), 1e-12) << "row " << i;  // the printed digits carry the solution
    if (orientation) {
      EXPECT_LE(e.tail<3>().norm(), 1e-12) << "row " << i;
    }
  }
}

TEST(CompensateCommand, SeedsInDegreesMillimetres) {
  CheckCompensation("analytic_derivative", testing::WellConditionedTargets(8, 41), false, true, true, false);
}

TEST(CompensateCommand, SeedsInRadiansMetres) {
  CheckCompensation("jacobian", testing::WellConditionedTargets(5, 42), true, true, true, true);
}

TEST(CompensateCommand, WithoutSeedsTheNominalInverseKinematicsIsSolved) {
  CheckCompensation("analytic_derivative", testing::WellConditionedTargets(3, 43), false, true, false, false);
}

TEST(CompensateCommand, PositionOnlyTargets) {
  CheckCompensation("jacobian", testing::WellConditionedTargets(4, 44, false), false, false, true, false);
}

TEST(CompensateCommand, OptionsFile) {
  TempDir dir;
  testing::WriteText(dir.path("t.csv"), TargetsCsv(testing::WellConditionedTargets(2, 45), false, true, true, false));
  testing::WriteText(dir.path("o.yaml"), "max_iterations: 0\n");
  const auto run =
      RunKincal("compensate" + Robots() + " --targets " + dir.path("t.csv") +
                " --method analytic_derivative --options " + dir.path("o.yaml") + " --out " + dir.path("j.csv"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable out = ParseCsv(testing::ReadText(dir.path("j.csv")), "j.csv");
  for (const CsvRow& row : out.rows) EXPECT_EQ(row.cells[FindColumn(out, "status")], "iteration_limit");
}

TEST(CompensateCommand, BadInputExitsWithStatus2AndWritesNothing) {
  TempDir dir;
  const std::string good = TargetsCsv(testing::WellConditionedTargets(2, 46), false, true, true, false);
  testing::WriteText(dir.path("good.csv"), good);
  testing::WriteText(dir.path("five_joints.csv"),
                     "x_mm,y_mm,z_mm,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg\n1,2,3,0,0,0,0,0\n");
  testing::WriteText(dir.path("no_z.csv"), "x_mm,y_mm\n1,2\n");
  testing::WriteText(dir.path("text.csv"), "x_mm,y_mm,z_mm\n1,2,abc\n");
  testing::WriteText(dir.path("encoders.csv"),
                     "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,enc1,enc2,enc3,enc4,enc5,enc6\n"
                     "0,0,0,0,0,0,1,2,3,0,0,0,0,0,0\n");
  testing::WriteText(dir.path("empty.csv"), "x_mm,y_mm,z_mm\n");
  testing::WriteText(dir.path("bad_options.yaml"), "lenght_scale: 1\n");
  const std::string out = dir.path("j.csv");
  const std::vector<std::string> cases = {
      "--targets " + dir.path("good.csv") + " --method newton",
      "--targets " + dir.path("missing.csv") + " --method jacobian",
      "--targets " + dir.path("five_joints.csv") + " --method jacobian",
      "--targets " + dir.path("no_z.csv") + " --method jacobian",
      "--targets " + dir.path("text.csv") + " --method jacobian",
      "--targets " + dir.path("encoders.csv") + " --method jacobian",
      "--targets " + dir.path("empty.csv") + " --method jacobian",
      "--targets " + dir.path("good.csv") + " --method jacobian --options " + dir.path("bad_options.yaml"),
      "--targets " + dir.path("good.csv"),  // no method
  };
  for (const std::string& args : cases) {
    const auto run = RunKincal("compensate" + Robots() + " " + args + " --out " + out);
    EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
  }
}

}  // namespace
}  // namespace kincal
