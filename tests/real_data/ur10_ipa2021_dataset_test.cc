// scripts/ur10_ipa2021_dataset on the real measurements: row counts, sessions and splits, values carried
// over unchanged (joints, positions), the orientation as the intrinsic XYZ Euler angles of the source
// computed independently with Eigen, the commanded poses beside the rows, and one-line errors with exit 2.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "tests/real_data/ur10_ipa2021_util.h"

namespace kincal::testing {
namespace {

TEST(Ur10Ipa2021Dataset, SeriesDFullPoseEvenOdd) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  std::string err;
  ASSERT_EQ(RunUr10Converter("'" + Ur10Series(kUr10D) + "' --pose full --split even-odd --out '" + dir.path("d.csv") +
                                 "' --goals '" + dir.path("goals.csv") + "'",
                             dir, &err),
            0)
      << err;
  const Dataset d = ReadDataset(dir.path("d.csv"));
  ASSERT_EQ(d.rows.size(), 632u);
  EXPECT_EQ(d.dof, 6);
  EXPECT_EQ(d.angle_unit.name, "rad");
  ASSERT_TRUE(d.HasOrientation());
  for (size_t i = 0; i < d.rows.size(); ++i) {
    EXPECT_EQ(d.rows[i].split, i % 2 == 0 ? Split::kTrain : Split::kTest) << i;
    EXPECT_EQ(d.rows[i].session, 1);
  }
  const char* joints[] = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                          "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
  for (int row : {0, 1, 317, 631}) {
    const auto source = Ur10SourceRow(Ur10Series(kUr10D), row);
    const Measurement& m = d.rows[row];
    for (int j = 0; j < 6; ++j) EXPECT_EQ(m.q[j], Ur10SourceValue(source, joints[j])) << row << " " << j;
    EXPECT_DOUBLE_EQ(m.p.x(), Ur10SourceValue(source, "measurement_x") * 1e-3);
    EXPECT_DOUBLE_EQ(m.p.y(), Ur10SourceValue(source, "measurement_y") * 1e-3);
    EXPECT_DOUBLE_EQ(m.p.z(), Ur10SourceValue(source, "measurement_z") * 1e-3);
    const double deg = M_PI / 180.0;
    const Eigen::Quaterniond expected(
        Eigen::AngleAxisd(Ur10SourceValue(source, "measurement_rx") * deg, Eigen::Vector3d::UnitX()) *
        Eigen::AngleAxisd(Ur10SourceValue(source, "measurement_ry") * deg, Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(Ur10SourceValue(source, "measurement_rz") * deg, Eigen::Vector3d::UnitZ()));
    EXPECT_LT(m.orientation->angularDistance(expected), 1e-12) << row;
  }
  // The commanded poses: one line per row, in the same order.
  const std::string goals = ReadText(dir.path("goals.csv"));
  std::stringstream lines(goals);
  std::string line;
  std::getline(lines, line);  // comment
  std::getline(lines, line);
  EXPECT_EQ(line, "goal_x_m,goal_y_m,goal_z_m,goal_roll_rad,goal_pitch_rad,goal_yaw_rad,session,split");
  std::getline(lines, line);
  EXPECT_EQ(line, "0.115748,0.63364,0.762898,1.5699,-0.000777623,-3.14154,1,train");
  int count = 1;
  while (std::getline(lines, line)) count += !line.empty();
  EXPECT_EQ(count, 632);
}

TEST(Ur10Ipa2021Dataset, CampaignBToCReregistered) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  std::string err;
  ASSERT_EQ(RunUr10Converter("'" + Ur10Series(kUr10B) + "' '" + Ur10Series(kUr10C) + "' --reregister 20 --out '" +
                                 dir.path("bc.csv") + "'",
                             dir, &err),
            0)
      << err;
  const Dataset bc = ReadDataset(dir.path("bc.csv"));
  ASSERT_EQ(bc.rows.size(), 1495u + 2773u);
  EXPECT_FALSE(bc.HasOrientation());
  int train_b = 0, train_c = 0, test_c = 0, other = 0;
  for (size_t i = 0; i < bc.rows.size(); ++i) {
    const Measurement& m = bc.rows[i];
    if (i < 1495 && m.session == 1 && m.split == Split::kTrain)
      ++train_b;
    else if (i >= 1495 && i < 1495 + 20 && m.session == 2 && m.split == Split::kTrain)
      ++train_c;
    else if (i >= 1495 + 20 && m.session == 2 && m.split == Split::kTest)
      ++test_c;
    else
      ++other;
  }
  EXPECT_EQ(train_b, 1495);
  EXPECT_EQ(train_c, 20);
  EXPECT_EQ(test_c, 2753);
  EXPECT_EQ(other, 0);
  // C's first row keeps its source values.
  const auto source = Ur10SourceRow(Ur10Series(kUr10C), 0);
  EXPECT_EQ(bc.rows[1495].q[1], Ur10SourceValue(source, "shoulder_lift_joint"));
  EXPECT_DOUBLE_EQ(bc.rows[1495].p.z(), Ur10SourceValue(source, "measurement_z") * 1e-3);
}

TEST(Ur10Ipa2021Dataset, SeriesAPositionsOnly) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  std::string err;
  ASSERT_EQ(RunUr10Converter("'" + Ur10Series(kUr10A) + "' --out '" + dir.path("a.csv") + "'", dir, &err), 0) << err;
  const Dataset a = ReadDataset(dir.path("a.csv"));
  EXPECT_EQ(a.rows.size(), 11911u);  // the data README says 11,910: the last line has no newline
  EXPECT_FALSE(a.HasSplit());
  const auto last = Ur10SourceRow(Ur10Series(kUr10A), 11910);
  EXPECT_DOUBLE_EQ(a.rows.back().p.x(), Ur10SourceValue(last, "measurement_x") * 1e-3);
}

TEST(Ur10Ipa2021Dataset, BadInputIsOneLineAndExitTwo) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  std::string err;
  // A hand-eye file is not a measurements file: the first missing column, with file:line:column.
  EXPECT_EQ(RunUr10Converter("'" + Ur10Series("Series_B/calibration_handeye.csv") + "'", dir, &err), 2);
  EXPECT_NE(err.find("calibration_handeye.csv:1:1: expected a column 'shoulder_pan_joint'"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  // A joint reading that is not a number (shoulder_pan_joint, the 8th field of line 2): its line and column.
  std::string text = ReadText(Ur10Series(kUr10D));
  const size_t line_start = text.find('\n') + 1;
  size_t at = line_start;
  for (int k = 0; k < 7; ++k) at = text.find(';', at) + 1;
  text.insert(at, "x");
  WriteText(dir.path("bad.csv"), text);
  EXPECT_EQ(RunUr10Converter("'" + dir.path("bad.csv") + "'", dir, &err), 2);
  const std::string where =
      "bad.csv:2:" + std::to_string(at - line_start + 1) + ": expected a number for shoulder_pan_joint";
  EXPECT_NE(err.find(where), std::string::npos) << err;
  EXPECT_EQ(RunUr10Converter("'" + Ur10Series(kUr10D) + "' --reregister 20", dir, &err), 2);
  EXPECT_NE(err.find("--reregister: expected at least two series"), std::string::npos) << err;
}

}  // namespace
}  // namespace kincal::testing
