// `kincal ik`: solutions that reach the targets on the robot (read back from the file), a status per row
// (a singular pose reached: singular; a pose out of reach: unreachable), every branch on request, and
// bad input as exit status 2 with one line; --options names the branch, and its bad values their line
// and column.
#include <sstream>

#include <gtest/gtest.h>

#include "framework/math.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;

std::vector<std::vector<std::string>> ReadCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(IkCli, SolvesEveryTargetAndWritesEveryBranchOnRequest) {
  const std::string robot_file = testing::SourcePath("examples/robots/ur10_dh.yaml");
  const Robot robot = ReadRobotFile(robot_file);
  testing::TempDir dir;
  std::ostringstream targets;
  targets.precision(17);
  targets << "x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  // The fourth: stretched (q3 = 0) with the wrist singular (q5 = 180 deg), one member of a continuum.
  const double configurations[4][6] = {{0.3, -1.2, 1.1, -0.5, 1.4, 0.2},
                                       {-2.0, -0.4, 2.0, 1.0, -0.7, 3.0},
                                       {1.0, -2.2, -1.5, 0.4, 2.2, -1.0},
                                       {-M_PI / 2, M_PI / 4, 0.0, -M_PI / 2, M_PI, M_PI / 2}};
  for (const auto& c : configurations) {
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(Eigen::Map<const Eigen::VectorXd>(c, 6));
    const Eigen::Quaterniond quat(T.linear());
    targets << T.translation().x() * 1e3 << "," << T.translation().y() * 1e3 << "," << T.translation().z() * 1e3 << ","
            << quat.w() << "," << quat.x() << "," << quat.y() << "," << quat.z() << "\n";
  }
  // A fifth target 5 m away: unreachable, finite joints.
  targets << "5000,0,0,1,0,0,0\n";
  testing::WriteText(dir.path("targets.csv"), targets.str());
  const auto r =
      RunKincal("ik " + robot_file + " --targets " + dir.path("targets.csv") + " --out " + dir.path("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = ReadCsv(testing::ReadText(dir.path("q.csv")));
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0][0], "q1_deg");
  EXPECT_EQ(rows[0][6], "status");
  for (int k = 1; k <= 5; ++k) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = std::stod(rows[k][j]) * M_PI / 180;
    ASSERT_TRUE(q.allFinite());
    if (k == 5) {
      EXPECT_EQ(rows[k][6], "unreachable");
      continue;
    }
    EXPECT_EQ(rows[k][6], k == 4 ? "singular" : "solved");
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(q);
    const Eigen::Isometry3d T_target =
        robot.model().ForwardKinematics(Eigen::Map<const Eigen::VectorXd>(configurations[k - 1], 6));
    // The file's 17 digits of mm and deg: a round trip to well below a micrometre.
    EXPECT_LT((T.translation() - T_target.translation()).norm(), 1e-9);
  }
  const auto all = RunKincal("ik " + robot_file + " --targets " + dir.path("targets.csv") + " --out " +
                             dir.path("all.csv") + " --all-branches");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const auto branches = ReadCsv(testing::ReadText(dir.path("all.csv")));
  EXPECT_EQ(branches[0][0], "target");
  int first_target = 0;
  for (const auto& row : branches) first_target += row[0] == "1";
  EXPECT_EQ(first_target, 8);  // a generic UR10 pose: 8 branches
}

TEST(IkCli, BadInputExitsWithStatusTwoAndOneLine) {
  const std::string robot_file = testing::SourcePath("examples/robots/irb120_mdh.yaml");
  testing::TempDir dir;
  testing::WriteText(dir.path("seeds.csv"), "x_mm,y_mm,z_mm,qw,qx,qy,qz,q1_deg,q2_deg\n300,0,500,1,0,0,0,0,0\n");
  testing::WriteText(dir.path("text.csv"), "x_mm,y_mm,z_mm\n300,abc,500\n");
  testing::WriteText(dir.path("q.csv"), "keep me");
  for (const std::string& targets : {dir.path("seeds.csv"), dir.path("text.csv"), dir.path("missing.csv")}) {
    const auto r = RunKincal("ik " + robot_file + " --targets " + targets + " --out " + dir.path("q.csv"));
    EXPECT_EQ(r.exit_code, 2) << targets;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(testing::ReadText(dir.path("q.csv")), "keep me");
  }
}

// --options: the named configuration picks the branch (the sign of q5, the wrist flip, on a generic
// IRB 120 pose, follows the option); a bad value names the file, line and column, exit 2.
TEST(IkCli, OptionsFileNamesTheBranchAndBadValuesGiveLineAndColumn) {
  const std::string robot_file = testing::SourcePath("examples/robots/irb120_mdh.yaml");
  const Robot robot = ReadRobotFile(robot_file);
  testing::TempDir dir;
  const double c[6] = {0.4, 0.3, -0.2, 0.7, 0.9, -0.5};
  const Eigen::Isometry3d T = robot.model().ForwardKinematics(Eigen::Map<const Eigen::VectorXd>(c, 6));
  const Eigen::Quaterniond quat(T.linear());
  std::ostringstream targets;
  targets.precision(17);
  targets << "x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
          << T.translation().x() * 1e3 << "," << T.translation().y() * 1e3 << "," << T.translation().z() * 1e3 << ","
          << quat.w() << "," << quat.x() << "," << quat.y() << "," << quat.z() << "\n";
  testing::WriteText(dir.path("targets.csv"), targets.str());
  for (const int sign : {-1, 1}) {
    testing::WriteText(dir.path("o.yaml"), "configuration: [0, 0, 0, 0, " + std::to_string(sign) + ", 0]\n");
    const auto r = RunKincal("ik " + robot_file + " --targets " + dir.path("targets.csv") + " --out " +
                             dir.path("q.csv") + " --options " + dir.path("o.yaml"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto rows = ReadCsv(testing::ReadText(dir.path("q.csv")));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[1][6], "solved");
    EXPECT_GT(sign * std::stod(rows[1][4]), 1.0) << "q5 " << rows[1][4];
  }
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"position_tolerance: 1e-9\nnumeric:\n  restarts: -3\n", "line 3, column 13:"},
      {"configuration: [0, 0, 2, 0, 0, 0]\n", "line 1, column 16:"},
      {"\nconfiguration: [0, 0, 1]\n", "line 2, column 16:"},
      {"singular_ratio: 1.5\n", "line 1, column 17:"},
      {"position_tolerance: 1 parsec\n", "line 1, column 21:"},
      {"use_closed_form: true\nrestarts: 3\n", "line 2, column 11:"},
  };
  testing::WriteText(dir.path("q.csv"), "keep me");
  for (const auto& [text, where] : bad) {
    testing::WriteText(dir.path("bad.yaml"), text);
    const auto r = RunKincal("ik " + robot_file + " --targets " + dir.path("targets.csv") + " --out " +
                             dir.path("q.csv") + " --options " + dir.path("bad.yaml"));
    EXPECT_EQ(r.exit_code, 2) << text;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("bad.yaml"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(where), std::string::npos) << text << " -> " << r.err;
    EXPECT_EQ(testing::ReadText(dir.path("q.csv")), "keep me");
  }
}

}  // namespace
}  // namespace kincal
