// Robot files (DESIGN.md "File contracts (v1)"): exact round trips, units at the edges, and one-line
// "file:line:column: what" messages for every kind of bad input.
#include <cstdio>
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "robot/robot_file.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::LoadExampleRobot;
using testing::ReadText;
using testing::SourcePath;

const char* const kExampleRobots[] = {"seed_nominal.yaml", "seed_identified.yaml", "puma560_dh.yaml",
                                      "puma560_mdh.yaml",  "ur10_dh.yaml",         "irb120_mdh.yaml"};

std::string WithoutCommentLines(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') continue;
    out += line + "\n";
  }
  return out;
}

// Bitwise equality of doubles: round trips must keep every digit, not just come close.
bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

void ExpectSameRobot(const Robot& a, const Robot& b) {
  ASSERT_EQ(a.model().convention(), b.model().convention());
  ASSERT_EQ(a.dof(), b.dof());
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.length_unit.name, b.length_unit.name);
  EXPECT_EQ(a.angle_unit.name, b.angle_unit.name);
  const auto names = a.model().ParameterNames();
  for (int i = 0; i < a.model().num_parameters(); ++i) {
    EXPECT_TRUE(SameBits(a.model().Parameters()[i], b.model().Parameters()[i]))
        << names[i] << ": " << a.model().Parameters()[i] << " vs " << b.model().Parameters()[i];
  }
  for (int i = 0; i < a.dof(); ++i) EXPECT_EQ(a.model().joint_type(i), b.model().joint_type(i));
  ASSERT_EQ(a.limits.size(), b.limits.size());
  for (size_t i = 0; i < a.limits.size(); ++i) {
    EXPECT_TRUE(SameBits(a.limits[i].first, b.limits[i].first));
    EXPECT_TRUE(SameBits(a.limits[i].second, b.limits[i].second));
  }
  ASSERT_EQ(a.drives.has_value(), b.drives.has_value());
  if (a.drives) {
    for (int i = 0; i < a.dof(); ++i) {
      EXPECT_TRUE(SameBits(a.drives->ratio[i], b.drives->ratio[i]));
      EXPECT_TRUE(SameBits(a.drives->counts_per_rev[i], b.drives->counts_per_rev[i]));
      EXPECT_TRUE(SameBits(a.drives->encoder_zero[i], b.drives->encoder_zero[i]));
    }
  }
  ASSERT_EQ(a.markers.size(), b.markers.size());
  for (const auto& [id, p] : a.markers) {
    ASSERT_TRUE(b.markers.count(id)) << id;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(SameBits(p[k], b.markers.at(id)[k])) << id;
  }
}

TEST(RobotFile, ExampleFilesWriteBackToTheirOwnText) {
  for (const char* file : kExampleRobots) {
    const std::string path = SourcePath(std::string("examples/robots/") + file);
    EXPECT_EQ(RobotToYaml(ReadRobotFile(path)), WithoutCommentLines(ReadText(path))) << file;
  }
}

TEST(RobotFile, ExampleFilesReadWriteReadKeepsEveryBit) {
  for (const char* file : kExampleRobots) {
    SCOPED_TRACE(file);
    const Robot first = LoadExampleRobot(file);
    ExpectSameRobot(first, ParseRobotYaml(RobotToYaml(first), "written"));
  }
}

// Decimals of up to 15 significant digits, in every unit system, with every optional section: the writer
// must give back exactly these decimals (the shortest text that maps to the same SI value).
const char* kAwkward = R"(name: awkward
convention: mdh
units: {length: LENGTH, angle: ANGLE}
joints:
  - {alpha: 0.1, a: 0.3, theta: -33.3333333333333, d: 1e-07}
  - {alpha: 89.98, a: 248.73, theta: 90.4, d: -2.11}
  - {alpha: -1.23456789012345, a: 0.0001, theta: 0, d: 7.00000000000001, type: prismatic}
drives:
  ratio: [7946.448979591837, -62.6111, 0.1]
  counts_per_rev: [2048, 4096, 1000]
  encoder_zero: [12, -7, 0.5]
limits: [[-170.5, 170.25], [-0.1, 0.3], [-12.5, 300]]
base: {xyz: [1000.1, -2.2, 0.003], rpy: [0.1, -0.2, 179.9]}
tool: {xyz: [40.01, 30.02, 100.03], rpy: [1e-05, 0, -0.3]}
markers:
  SMR1: [0.1, 0.2, 0.3]
  SMR2: [-150.5, 12.25, 1e-06]
)";

std::string Awkward(const std::string& length, const std::string& angle) {
  std::string text = kAwkward;
  text.replace(text.find("LENGTH"), 6, length);
  text.replace(text.find("ANGLE"), 5, angle);
  return text;
}

const char* const kLengthUnits[] = {"m", "cm", "mm", "um"};
const char* const kAngleUnits[] = {"deg", "rad"};

TEST(RobotFile, WriterGivesBackTheDecimalsOfTheFile) {
  for (const char* length : kLengthUnits) {
    for (const char* angle : kAngleUnits) {
      SCOPED_TRACE(std::string(length) + ", " + angle);
      const std::string text = Awkward(length, angle);
      EXPECT_EQ(RobotToYaml(ParseRobotYaml(text, "awkward.yaml")), text);
    }
  }
}

// Random 17-digit decimals: some have a shorter decimal with the same SI value, so the text may change,
// but file -> SI -> file -> SI must give the same bits, and writing again the same text.
std::string RandomRobotText(uint64_t seed, const std::string& length, const std::string& angle) {
  Rng rng(seed);
  const auto between = [&](double low, double high) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", rng.Uniform(low, high));
    return std::string(buffer);
  };
  const auto number = [&](double scale) { return between(-scale, scale); };
  std::string text = "name: random\nconvention: " + std::string(seed % 2 ? "mdh" : "dh") +
                     "\nunits: {length: " + length + ", angle: " + angle + "}\njoints:\n";
  for (int i = 0; i < 7; ++i) {
    text += "  - {alpha: " + number(180) + ", a: " + number(1000) + ", theta: " + number(180) + ", d: " + number(1000) +
            "}\n";
  }
  text += "limits: [";
  for (int i = 0; i < 7; ++i)
    text += std::string(i ? ", " : "") + "[" + between(-200, -1) + ", " + between(1, 200) + "]";
  text += "]\n";
  text += "base: {xyz: [" + number(5000) + ", " + number(5000) + ", " + number(5000) + "], rpy: [" + number(180) +
          ", " + number(90) + ", " + number(180) + "]}\n";
  text += "tool: {xyz: [" + number(200) + ", " + number(200) + ", " + number(200) + "], rpy: [" + number(180) + ", " +
          number(90) + ", " + number(180) + "]}\n";
  text += "markers:\n  A: [" + number(100) + ", " + number(100) + ", " + number(100) + "]\n";
  return text;
}

TEST(RobotFile, ReadWriteReadKeepsEveryBitInEveryUnit) {
  uint64_t seed = 1;
  for (const char* length : kLengthUnits) {
    for (const char* angle : kAngleUnits) {
      for (int trial = 0; trial < 5; ++trial, ++seed) {
        SCOPED_TRACE(std::string(length) + ", " + angle + ", seed " + std::to_string(seed));
        const Robot first = ParseRobotYaml(RandomRobotText(seed, length, angle), "random.yaml");
        const std::string written = RobotToYaml(first);
        const Robot second = ParseRobotYaml(written, "written.yaml");
        ExpectSameRobot(first, second);
        EXPECT_EQ(RobotToYaml(second), written);
      }
    }
  }
}

TEST(RobotFile, UnitsAreConvertedToSiOnReading) {
  const Robot mm_deg = ParseRobotYaml(Awkward("mm", "deg"), "mm_deg.yaml");
  const Robot m_rad = ParseRobotYaml(Awkward("m", "rad"), "m_rad.yaml");
  const KinematicModel& a = mm_deg.model();
  const KinematicModel& b = m_rad.model();
  EXPECT_DOUBLE_EQ(a.Parameter("a_2"), 0.24873);
  EXPECT_DOUBLE_EQ(b.Parameter("a_2"), 248.73);
  EXPECT_DOUBLE_EQ(a.Parameter("theta_2"), 90.4 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(b.Parameter("theta_2"), 90.4);
  EXPECT_DOUBLE_EQ(a.Parameter("base_yaw"), 179.9 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(a.Parameter("tool_z"), 0.10003);
  // A prismatic joint's limits are lengths, a revolute joint's are angles.
  EXPECT_DOUBLE_EQ(mm_deg.limits[0].first, -170.5 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(mm_deg.limits[2].second, 0.3);
  EXPECT_DOUBLE_EQ(mm_deg.markers.at("SMR2").x(), -0.1505);
  // Ratios and counts carry no unit.
  EXPECT_EQ(mm_deg.drives->ratio, m_rad.drives->ratio);
  EXPECT_EQ(mm_deg.model().joint_type(2), JointType::kPrismatic);
}

TEST(RobotFile, SameRobotInMillimetresAndMetresGivesTheSamePose) {
  const Robot mm = LoadExampleRobot("puma560_dh.yaml");
  // Rewrite the table in metres and radians by hand, as a user would.
  const std::string metres = R"(name: puma_in_metres
convention: dh
units: {length: m, angle: rad}
joints:
  - {alpha: 1.5707963267948966, a: 0, theta: 0, d: 0}
  - {alpha: 0, a: 0.4318, theta: 0, d: 0}
  - {alpha: -1.5707963267948966, a: 0.0203, theta: 0, d: 0.15005}
  - {alpha: 1.5707963267948966, a: 0, theta: 0, d: 0.4318}
  - {alpha: -1.5707963267948966, a: 0, theta: 0, d: 0}
  - {alpha: 0, a: 0, theta: 0, d: 0}
)";
  const Robot m = ParseRobotYaml(metres, "puma_in_metres.yaml");
  Eigen::VectorXd q(6);
  q << 0.1, -0.7, 1.3, 2.1, -0.4, 3.0;
  const Eigen::Isometry3d a = mm.model().ForwardKinematics(q);
  const Eigen::Isometry3d b = m.model().ForwardKinematics(q);
  EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(RobotFile, WritesInTheUnitsItWasReadIn) {
  const Robot ur10 = LoadExampleRobot("ur10_dh.yaml");
  EXPECT_EQ(ur10.length_unit.name, "m");
  EXPECT_EQ(ur10.angle_unit.name, "deg");
  EXPECT_NE(RobotToYaml(ur10).find("units: {length: m, angle: deg}"), std::string::npos);
  EXPECT_NE(RobotToYaml(ur10).find("d: 0.163941}"), std::string::npos);
}

TEST(RobotFile, DefaultsWhenOptionalSectionsAreAbsent) {
  const Robot r = ParseRobotYaml(
      "convention: dh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: 0, a: 100, theta: 0, d: 0}\n", "min.yaml");
  EXPECT_EQ(r.name, "robot");
  EXPECT_FALSE(r.drives.has_value());
  EXPECT_TRUE(r.limits.empty());
  EXPECT_DOUBLE_EQ(r.Limit(0).first, -M_PI / 2);  // +-90 deg when the file gives none
  EXPECT_TRUE(r.model().base().isApprox(Eigen::Isometry3d::Identity(), 0.0));
  EXPECT_TRUE(r.model().tool().isApprox(Eigen::Isometry3d::Identity(), 0.0));
}

TEST(RobotFile, WriteRobotFileReplacesTheFileWhole) {
  testing::TempDir dir;
  const std::string path = dir.path("robot.yaml");
  testing::WriteText(path, "old content that is longer than nothing at all\n");
  const Robot r = LoadExampleRobot("irb120_mdh.yaml");
  WriteRobotFile(r, path);
  EXPECT_EQ(ReadText(path), RobotToYaml(r));
  ExpectSameRobot(r, ReadRobotFile(path));
}

// ---- Bad input: each message is one line and points at the offending token. ----------------------

// Line numbers below refer to this text (1-based); each case replaces one line.
const char* kGood = R"(name: r
convention: mdh
units: {length: mm, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 100, theta: 0, d: 0}
drives:
  ratio: [100, 120]
  counts_per_rev: [2048, 2048]
limits: [[-90, 90], [-45, 45]]
tool: {xyz: [1, 2, 3], rpy: [0, 0, 0]}
)";

std::string ReplaceLine(int line, const std::string& replacement) {
  std::istringstream in(kGood);
  std::string text, l;
  for (int i = 1; std::getline(in, l); ++i) text += (i == line ? replacement : l) + "\n";
  return text;
}

std::string ErrorOf(const std::string& text) {
  try {
    ParseRobotYaml(text, "robot.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

struct BadCase {
  const char* label;
  int line;
  const char* replacement;
  const char* where;  // expected "file:line:col" prefix
  const char* what;   // expected part of the message
};
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.label; }

class BadRobotFile : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadRobotFile, NamesFileLineColumnAndReason) {
  const BadCase& c = GetParam();
  const std::string message = ErrorOf(ReplaceLine(c.line, c.replacement));
  EXPECT_EQ(message.rfind(std::string(c.where) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(c.what), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadRobotFile,
    ::testing::Values(
        BadCase{"unknown_top_level_key", 10, "limit: [[-90, 90], [-45, 45]]", "robot.yaml:10:1", "unknown key 'limit'"},
        BadCase{"unknown_row_key", 6, "  - {alpha: 90, a: 100, theta: 0, d: 0, b: 1}", "robot.yaml:6:41",
                "unknown key 'b' in joint row 2"},
        BadCase{"missing_row_key", 6, "  - {alpha: 90, a: 100, theta: 0}", "robot.yaml:6:5", "lacks 'd'"},
        BadCase{"missing_units", 3, "", "robot.yaml:1:1", "missing key 'units'"},
        BadCase{"wrong_type_list_for_number", 6, "  - {alpha: [90], a: 100, theta: 0, d: 0}", "robot.yaml:6:13",
                "expected a number for alpha_2"},
        BadCase{"wrong_type_text_for_number", 6, "  - {alpha: ninety, a: 100, theta: 0, d: 0}", "robot.yaml:6:13",
                "expected a number for alpha_2"},
        BadCase{"wrong_type_row_not_map", 5, "  - 5", "robot.yaml:5:5", "expected a joint row to be a map"},
        BadCase{"wrong_count_xyz", 11, "tool: {xyz: [1, 2], rpy: [0, 0, 0]}", "robot.yaml:11:13",
                "expected 3 numbers for tool.xyz, got 2"},
        BadCase{"wrong_count_ratios", 8, "  ratio: [100, 120, 140]", "robot.yaml:8:10",
                "expected 2 numbers for drives.ratio, got 3"},
        BadCase{"wrong_count_limits", 10, "limits: [[-90, 90]]", "robot.yaml:10:9", "2 [min, max] pairs"},
        BadCase{"bad_length_unit", 3, "units: {length: furlong, angle: deg}", "robot.yaml:3:8",
                "unknown length unit 'furlong'"},
        BadCase{"bad_angle_unit", 3, "units: {length: mm, angle: grad}", "robot.yaml:3:8", "unknown angle unit 'grad'"},
        BadCase{"nan", 6, "  - {alpha: .nan, a: 100, theta: 0, d: 0}", "robot.yaml:6:13",
                "expected a number for alpha_2"},
        BadCase{"nan_word", 6, "  - {alpha: 90, a: nan, theta: 0, d: 0}", "robot.yaml:6:20",
                "expected a number for a_2"},
        BadCase{"infinity", 11, "tool: {xyz: [1, 2, .inf], rpy: [0, 0, 0]}", "robot.yaml:11:20",
                "expected a number for tool.xyz"},
        BadCase{"unknown_convention", 2, "convention: craig", "robot.yaml:2:13", "unknown convention 'craig'"},
        BadCase{"bad_joint_type", 6, "  - {alpha: 90, a: 100, theta: 0, d: 0, type: spherical}", "robot.yaml:6:47",
                "expected type revolute or prismatic"},
        BadCase{"limits_reversed", 10, "limits: [[-90, 90], [45, -45]]", "robot.yaml:10:21", "min < max"},
        BadCase{"zero_ratio", 8, "  ratio: [100, 0]", "robot.yaml:8:3", "ratio of joint 2 must be finite and non-zero"},
        BadCase{"invalid_yaml", 6, "  - {alpha: 90, a: 100, theta: 0, d: 0", "robot.yaml:7:7",
                "invalid YAML: end of map flow not found"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.label); });

TEST(RobotFile, UnreadableFileNamesThePath) {
  try {
    ReadRobotFile("/nonexistent/robot.yaml");
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace kincal
