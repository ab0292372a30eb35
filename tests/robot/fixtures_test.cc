// The robot file's `fixtures:` section: units, round trips to the byte and to the bit, and one-line
// file:line:column messages for bad input.
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "robot/robot_file.h"

namespace kincal {
namespace {

const char* kFixtureRobot = R"(name: r
convention: mdh
units: {length: mm, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 100, theta: 0, d: 0}
fixtures:
  pivots: {P1: {xyz: [700, 0, 300]}, P2: {xyz: [0, 700, 300], sd: 1}}
  planes: {table: {normal: [0, 0, 1], offset: 300, sd: 0.5, sd_angle: 0.1}}
  points: {socket: {xyz: [500, 200, 100], sd: 2}}
)";

TEST(Fixtures, AreReadInSiWithTheirPriors) {
  const Robot robot = ParseRobotYaml(kFixtureRobot, "r.yaml");
  ASSERT_EQ(robot.fixtures.items.size(), 4u);
  const Fixture* p1 = robot.fixtures.Find(Fixture::Type::kPivot, "P1");
  ASSERT_NE(p1, nullptr);
  EXPECT_TRUE(p1->known);
  EXPECT_TRUE(p1->position.isApprox(Eigen::Vector3d(0.7, 0.0, 0.3)));
  const Fixture* p2 = robot.fixtures.Find(Fixture::Type::kPivot, "P2");
  ASSERT_NE(p2, nullptr);
  EXPECT_FALSE(p2->known);
  EXPECT_DOUBLE_EQ(p2->sd, 1e-3);
  const Fixture* table = robot.fixtures.Find(Fixture::Type::kPlane, "table");
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(table->normal, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(table->offset, 0.3);
  EXPECT_DOUBLE_EQ(table->sd, 0.5e-3);
  EXPECT_DOUBLE_EQ(table->sd_angle, 0.1 * M_PI / 180.0);
  EXPECT_FALSE(table->known);
  EXPECT_EQ(robot.fixtures.Find(Fixture::Type::kPlane, "P1"), nullptr);  // types do not share names
  EXPECT_NE(robot.fixtures.Find(Fixture::Type::kPoint, "socket"), nullptr);
  EXPECT_NO_THROW(robot.fixtures.Validate());
  EXPECT_EQ(FixtureTypeOf(MeasurementKind::kDistance), Fixture::Type::kPivot);
  EXPECT_EQ(FixtureTypeOf(MeasurementKind::kPlane), Fixture::Type::kPlane);
  EXPECT_EQ(FixtureTypeOf(MeasurementKind::kFixedPoint), Fixture::Type::kPoint);
  EXPECT_THROW(FixtureTypeOf(MeasurementKind::kPoint), std::invalid_argument);
}

TEST(Fixtures, ReadWriteReadKeepsEveryBitAndWriteIsStable) {
  for (const char* units : {"{length: mm, angle: deg}", "{length: m, angle: rad}"}) {
    std::string text = kFixtureRobot;
    text.replace(text.find("{length: mm, angle: deg}"), 24, units);
    const Robot first = ParseRobotYaml(text, "r.yaml");
    const std::string written = RobotToYaml(first);
    const Robot second = ParseRobotYaml(written, "w.yaml");
    EXPECT_EQ(RobotToYaml(second), written);
    ASSERT_EQ(second.fixtures.items.size(), first.fixtures.items.size());
    for (size_t i = 0; i < first.fixtures.items.size(); ++i) {
      const Fixture& a = first.fixtures.items[i];
      const Fixture& b = second.fixtures.items[i];
      EXPECT_EQ(a.type, b.type);
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.position, b.position);
      EXPECT_EQ(a.normal, b.normal);
      EXPECT_EQ(std::memcmp(&a.offset, &b.offset, sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(&a.sd, &b.sd, sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(&a.sd_angle, &b.sd_angle, sizeof(double)), 0);
      EXPECT_EQ(a.known, b.known);
    }
  }
}

TEST(Fixtures, ARobotWithoutThemWritesNoSection) {
  std::string text = kFixtureRobot;
  text = text.substr(0, text.find("fixtures:"));
  const Robot robot = ParseRobotYaml(text, "r.yaml");
  EXPECT_TRUE(robot.fixtures.empty());
  EXPECT_EQ(RobotToYaml(robot).find("fixtures"), std::string::npos);
}

std::string FixtureErrorOf(const std::string& fixtures) {
  std::string text = kFixtureRobot;
  text = text.substr(0, text.find("fixtures:")) + fixtures;
  try {
    ParseRobotYaml(text, "r.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

struct FixtureCase {
  const char* label;
  const char* fixtures;  // from line 7 on
  const char* where;
  const char* what;
};
void PrintTo(const FixtureCase& c, std::ostream* os) { *os << c.label; }

class BadFixtures : public ::testing::TestWithParam<FixtureCase> {};

TEST_P(BadFixtures, NamesFileLineColumnAndReason) {
  const FixtureCase& c = GetParam();
  const std::string message = FixtureErrorOf(c.fixtures);
  EXPECT_EQ(message.rfind(std::string(c.where) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(c.what), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadFixtures,
    ::testing::Values(
        FixtureCase{"unknown_section", "fixtures: {balls: {}}\n", "r.yaml:7:12", "unknown key 'balls' in fixtures"},
        FixtureCase{"not_a_map", "fixtures: [1, 2]\n", "r.yaml:7:11", "expected fixtures to be a map"},
        FixtureCase{"pivot_without_xyz", "fixtures:\n  pivots: {P1: {sd: 1}}\n", "r.yaml:8:16", "pivots.P1 needs 'xyz'"},
        FixtureCase{"pivot_short_xyz", "fixtures:\n  pivots: {P1: {xyz: [1, 2]}}\n", "r.yaml:8:22",
                "expected 3 numbers for pivots.P1.xyz"},
        FixtureCase{"negative_sd", "fixtures:\n  points: {S: {xyz: [1, 2, 3], sd: -1}}\n", "r.yaml:8:36",
                "expected points.S.sd >= 0"},
        FixtureCase{"plane_normal_not_unit", "fixtures:\n  planes: {T: {normal: [0, 0, 2], offset: 1}}\n", "r.yaml:8:24",
                "expected a unit normal for planes.T"},
        FixtureCase{"plane_without_offset", "fixtures:\n  planes: {T: {normal: [0, 0, 1]}}\n", "r.yaml:8:15",
                "planes.T needs 'normal' and 'offset'"},
        FixtureCase{"plane_with_xyz", "fixtures:\n  planes: {T: {normal: [0, 0, 1], offset: 1, xyz: [1, 2, 3]}}\n",
                "r.yaml:8:46", "unknown key 'xyz' in planes.T"},
        FixtureCase{"pivot_with_sd_angle", "fixtures:\n  pivots: {P: {xyz: [1, 2, 3], sd_angle: 1}}\n", "r.yaml:8:32",
                "unknown key 'sd_angle' in pivots.P"},
        FixtureCase{"given_twice", "fixtures:\n  pivots:\n    P: {xyz: [1, 2, 3]}\n    P: {xyz: [1, 2, 3]}\n",
                "r.yaml:10:5", "pivot 'P' given twice"},
        FixtureCase{"text_for_number", "fixtures:\n  points: {S: {xyz: [1, two, 3]}}\n", "r.yaml:8:25",
                "expected a number for points.S.xyz"}),
    [](const ::testing::TestParamInfo<FixtureCase>& info) { return std::string(info.param.label); });

}  // namespace
}  // namespace kincal
