// Dataset CSV files (DESIGN.md "File contracts (v1)"): exact round trips in every unit, and one-line
// "file:line:column: what" messages for bad input.
#include <cstring>

#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "framework/random.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Every optional column, values in file units drawn as random 17-digit decimals.
std::string RandomCsv(uint64_t seed, const std::string& angle, const std::string& length, int rows) {
  Rng rng(seed);
  const auto number = [&](double scale) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", rng.Uniform(-scale, scale));
    return std::string(buffer);
  };
  std::string text = "# made by a test\n# second comment\n";
  for (int j = 1; j <= 3; ++j) text += "q" + std::to_string(j) + "_" + angle + ",";
  text += "x_" + length + ",y_" + length + ",z_" + length + ",enc1,enc2,enc3,qw,qx,qy,qz,sweep,marker,session,split\n";
  for (int r = 0; r < rows; ++r) {
    for (int j = 0; j < 3; ++j) text += number(180) + ",";
    for (int k = 0; k < 3; ++k) text += number(2000) + ",";
    for (int j = 0; j < 3; ++j) text += std::to_string(static_cast<int64_t>(rng.Uniform(-1e9, 1e9))) + ",";
    const Eigen::Quaterniond quat =
        Eigen::Quaterniond(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    for (double v : {quat.w(), quat.x(), quat.y(), quat.z()}) {
      char buffer[40];
      std::snprintf(buffer, sizeof(buffer), "%.17g", v);
      text += std::string(buffer) + ",";
    }
    text += std::to_string(r % 4) + "," + (r % 3 ? "SMR" + std::to_string(r % 3) : "") + "," + std::to_string(r % 2) +
            "," + (r % 5 == 0 ? "test" : "train") + "\n";
  }
  return text;
}

void ExpectSameData(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.dof, b.dof);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  EXPECT_EQ(a.comments, b.comments);
  for (size_t r = 0; r < a.rows.size(); ++r) {
    const Measurement& x = a.rows[r];
    const Measurement& y = b.rows[r];
    for (int j = 0; j < a.dof; ++j) EXPECT_TRUE(SameBits(x.q[j], y.q[j])) << "row " << r;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(SameBits(x.p[k], y.p[k])) << "row " << r;
    EXPECT_EQ(x.encoders, y.encoders);
    ASSERT_EQ(x.orientation.has_value(), y.orientation.has_value());
    if (x.orientation) {
      EXPECT_EQ(x.orientation->coeffs(), y.orientation->coeffs());
    }
    EXPECT_EQ(x.sweep, y.sweep);
    EXPECT_EQ(x.marker, y.marker);
    EXPECT_EQ(x.session, y.session);
    EXPECT_EQ(x.split, y.split);
  }
}

TEST(Dataset, ReadWriteReadKeepsEveryBitInEveryUnit) {
  uint64_t seed = 10;
  for (const char* angle : {"deg", "rad"}) {
    for (const char* length : {"mm", "m", "um"}) {
      SCOPED_TRACE(std::string(angle) + ", " + length);
      const Dataset first = ParseDatasetCsv(RandomCsv(seed++, angle, length, 40), "random.csv");
      EXPECT_EQ(first.angle_unit.name, angle);
      EXPECT_EQ(first.length_unit.name, length);
      const std::string written = DatasetToCsv(first);
      const Dataset second = ParseDatasetCsv(written, "written.csv");
      ExpectSameData(first, second);
      EXPECT_EQ(DatasetToCsv(second), written);
    }
  }
}

TEST(Dataset, ColumnsAndUnitsAreReadAsSi) {
  const std::string text =
      "# a comment\r\n"
      "q1_deg,q2_rad,x_mm,y_mm,z_mm,sweep,marker,session,split\r\n"
      "\r\n"
      "90,0.5,1000,-20,0.5,2,SMR1,3,test\r\n"
      "# a comment between rows is skipped\n"
      "-45,-0.25,1,2,3,,,,\n";
  const Dataset d = ParseDatasetCsv(text, "mixed.csv");
  ASSERT_EQ(d.dof, 2);
  ASSERT_EQ(d.rows.size(), 2u);
  EXPECT_EQ(d.header_line, 2);
  EXPECT_EQ(d.comments, std::vector<std::string>{"a comment"});
  EXPECT_DOUBLE_EQ(d.rows[0].q[0], M_PI / 2);
  EXPECT_DOUBLE_EQ(d.rows[0].q[1], 0.5);  // units per column
  EXPECT_DOUBLE_EQ(d.rows[0].p.x(), 1.0);
  EXPECT_DOUBLE_EQ(d.rows[0].p.z(), 0.0005);
  EXPECT_EQ(d.rows[0].sweep, 2);
  EXPECT_EQ(d.rows[0].marker, "SMR1");
  EXPECT_EQ(d.rows[0].session, 3);
  EXPECT_EQ(d.rows[0].split, Split::kTest);
  EXPECT_EQ(d.rows[0].line, 4);
  EXPECT_EQ(d.rows[1].line, 6);
  EXPECT_EQ(d.rows[1].sweep, 0);  // empty cells: free pose, no marker, session 0, no split
  EXPECT_EQ(d.rows[1].marker, "");
  EXPECT_EQ(d.rows[1].split, Split::kNone);
  EXPECT_FALSE(d.HasEncoders());
  EXPECT_FALSE(d.HasOrientation());
  EXPECT_TRUE(d.HasSplit());
  EXPECT_EQ(d.Subset(Split::kTest).rows.size(), 1u);
  EXPECT_EQ(d.Subset(Split::kTrain).rows.size(), 0u);
}

TEST(Dataset, WriteDatasetReplacesTheFileWhole) {
  testing::TempDir dir;
  const std::string path = dir.path("data.csv");
  testing::WriteText(path, std::string(10000, 'x'));
  const Dataset d = ParseDatasetCsv(RandomCsv(3, "deg", "mm", 5), "random.csv");
  WriteDataset(d, path);
  EXPECT_EQ(testing::ReadText(path), DatasetToCsv(d));
  ExpectSameData(d, ReadDataset(path));
}

// ---- Bad input -----------------------------------------------------------------------------------

std::string ErrorOf(const std::string& text, int robot_dof = 2) {
  try {
    ParseDatasetCsv(text, "data.csv").Validate(robot_dof);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

struct BadCase {
  const char* label;
  const char* text;
  int robot_dof;
  const char* where;
  const char* what;
};
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.label; }

class BadDataset : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadDataset, NamesFileLineColumnAndReason) {
  const BadCase& c = GetParam();
  const std::string message = ErrorOf(c.text, c.robot_dof);
  EXPECT_EQ(message.rfind(std::string(c.where) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(c.what), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadDataset,
    ::testing::Values(BadCase{"ragged_row", "q1_deg,q2_deg,x_mm,y_mm,z_mm\n1,2,3,4,5\n1,2,3,4\n", 2, "data.csv:3:1",
                              "expected 5 comma-separated values, got 4"},
                      BadCase{"nan", "q1_deg,q2_deg,x_mm,y_mm,z_mm\n1,2,3,4,5\n1,2,nan,4,5\n", 2, "data.csv:3:5",
                              "expected a finite number for x, got 'nan'"},
                      BadCase{"infinite", "q1_deg,q2_deg,x_mm,y_mm,z_mm\n1,inf,3,4,5\n", 2, "data.csv:2:3",
                              "expected a finite number for a joint angle"},
                      BadCase{"text", "q1_deg,q2_deg,x_mm,y_mm,z_mm\n1,2,3,4,five\n", 2, "data.csv:2:9", "got 'five'"},
                      BadCase{"wrong_joint_count", "# comment\nq1_deg,q2_deg,q3_deg,x_mm,y_mm,z_mm\n1,2,3,4,5,6\n", 2,
                              "data.csv:2:1", "the dataset has 3 joint columns but the robot has 2 joints"},
                      BadCase{"missing_joint_column", "q1_deg,q3_deg,x_mm,y_mm,z_mm\n1,2,3,4,5\n", 2, "data.csv:1:1",
                              "joint column q2_ is missing"},
                      BadCase{"unknown_column", "q1_deg,q2_deg,x_mm,y_mm,z_mm,temperature\n1,2,3,4,5,6\n", 2,
                              "data.csv:1:30", "unknown column 'temperature'"},
                      BadCase{"bad_angle_unit", "q1_deg,q2_grad,x_mm,y_mm,z_mm\n1,2,3,4,5\n", 2, "data.csv:1:8",
                              "unknown unit 'grad' in column 'q2_grad'"},
                      BadCase{"bad_length_unit", "q1_deg,q2_deg,x_in,y_in,z_in\n1,2,3,4,5\n", 2, "data.csv:1:15",
                              "unknown length unit 'in'"},
                      BadCase{"mixed_length_units", "q1_deg,q2_deg,x_mm,y_m,z_mm\n1,2,3,4,5\n", 2, "data.csv:1:20",
                              "x, y and z must share one length unit"},
                      BadCase{"missing_position", "q1_deg,q2_deg,x_mm,y_mm\n1,2,3,4\n", 2, "data.csv:1:1",
                              "expected position columns"},
                      BadCase{"non_unit_quaternion",
                              "q1_deg,q2_deg,x_mm,y_mm,z_mm,qw,qx,qy,qz\n1,2,3,4,5,1,0,0,0\n1,2,3,4,5,1,0.1,0,0\n", 2,
                              "data.csv:3:11", "expected a unit quaternion"},
                      BadCase{"partial_quaternion", "q1_deg,q2_deg,x_mm,y_mm,z_mm,qw,qx\n1,2,3,4,5,1,0\n", 2,
                              "data.csv:1:1", "expected all of qw, qx, qy, qz or none"},
                      BadCase{"fractional_encoder", "q1_deg,q2_deg,x_mm,y_mm,z_mm,enc1,enc2\n1,2,3,4,5,10,10.5\n", 2,
                              "data.csv:2:14", "expected an integer for an encoder count"},
                      BadCase{"encoder_count_mismatch", "q1_deg,q2_deg,x_mm,y_mm,z_mm,enc1\n1,2,3,4,5,10\n", 2,
                              "data.csv:1:1", "expected one enc column per joint"},
                      BadCase{"bad_split", "q1_deg,q2_deg,x_mm,y_mm,z_mm,split\n1,2,3,4,5,validation\n", 2,
                              "data.csv:2:11", "expected split 'train' or 'test', got 'validation'"},
                      BadCase{"sweep_out_of_range", "q1_deg,q2_deg,x_mm,y_mm,z_mm,sweep\n1,2,3,4,5,0\n1,2,3,4,5,3\n", 2,
                              "data.csv:3", "sweep index 3 out of range 0..2"},
                      BadCase{"empty_file", "# only a comment\n", 2, "data.csv:1:1", "expected a header row"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.label); });

}  // namespace
}  // namespace kincal
