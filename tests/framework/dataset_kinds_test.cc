// The measurement kinds of a dataset (point, partial point, distance, plane, fixed point): what each row
// reads, round trips to the byte with every kind in one file, and one-line file:line:column messages.
#include <cstring>

#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "framework/random.h"

namespace kincal {
namespace {

// Random rows of every kind in one file, in file units, with the columns every kind keeps.
std::string RandomMixedCsv(uint64_t seed, const std::string& length, int rows) {
  Rng rng(seed);
  const auto number = [&](double lo, double hi) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", rng.Uniform(lo, hi));
    return std::string(buffer);
  };
  std::string text = "# every kind\nq1_deg,q2_deg,x_" + length + ",y_" + length + ",z_" + length + ",distance_" +
                     length + ",pivot,plane,point,qw,qx,qy,qz,marker,session,split\n";
  for (int r = 0; r < rows; ++r) {
    text += number(-180, 180) + "," + number(-180, 180) + ",";
    const int kind = r % 5;
    std::string xyz = ",,", measure = ",,,", quat = ",,,";
    if (kind == 0) {
      xyz = number(-2000, 2000) + "," + number(-2000, 2000) + "," + number(-2000, 2000);
      if (r % 2) {
        const Eigen::Quaterniond q = Eigen::Quaterniond(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal()).normalized();
        char b[120];
        std::snprintf(b, sizeof(b), "%.17g,%.17g,%.17g,%.17g", q.w(), q.x(), q.y(), q.z());
        quat = b;
      }
    } else if (kind == 1) {
      xyz = (r % 3 == 0 ? "" : number(-2000, 2000)) + ",," + number(-2000, 2000);  // a partial point
    } else if (kind == 2) {
      measure = number(0, 1500) + ",P" + std::to_string(r % 3) + ",,";
    } else if (kind == 3) {
      measure = ",,table" + std::to_string(r % 2) + ",";
    } else {
      measure = ",,,socket";
    }
    text += xyz + "," + measure + "," + quat + "," + (r % 2 ? "SMR1" : "") + "," + std::to_string(r % 3) + "," +
            (r % 4 ? "train" : "test") + "\n";
  }
  return text;
}

TEST(DatasetKinds, EveryKindInOneFileRoundTripsToTheByte) {
  for (const char* length : {"mm", "m"}) {
    SCOPED_TRACE(length);
    const std::string text = RandomMixedCsv(7, length, 60);
    const Dataset first = ParseDatasetCsv(text, "mixed.csv");
    // Written in the file's own column order; written, read and written again: the very same bytes.
    const std::string written = DatasetToCsv(first);
    EXPECT_EQ(written.substr(0, written.find('\n', 13)), text.substr(0, text.find('\n', 13)));
    const Dataset second = ParseDatasetCsv(written, "written.csv");
    EXPECT_EQ(DatasetToCsv(second), written);
    ASSERT_EQ(second.rows.size(), first.rows.size());
    for (size_t r = 0; r < first.rows.size(); ++r) {
      const Measurement& a = first.rows[r];
      const Measurement& b = second.rows[r];
      EXPECT_EQ(a.kind, b.kind);
      EXPECT_EQ(a.axes, b.axes);
      EXPECT_EQ(std::memcmp(&a.distance, &b.distance, sizeof(double)), 0);
      EXPECT_EQ(a.fixture, b.fixture);
      EXPECT_EQ(a.p, b.p);
    }
  }
}

TEST(DatasetKinds, RowsReadWhatTheirKindMeasures) {
  const std::string text =
      "q1_deg,q2_deg,x_mm,y_mm,z_mm,distance_mm,pivot,plane,point\n"
      "1,2,100,200,300,,,,\n"
      "1,2,,,300,,,,\n"
      "1,2,,,,700.5,P1,,\n"
      "1,2,,,,,,table,\n"
      "1,2,,,,,,,socket\n"
      "1,2,,,,0,P2,,\n"
      "1,2,,,,650,P1,,\n";
  const Dataset d = ParseDatasetCsv(text, "kinds.csv");
  d.Validate(2);
  ASSERT_EQ(d.rows.size(), 7u);
  EXPECT_TRUE(d.rows[0].IsFullPoint());
  EXPECT_EQ(d.rows[1].kind, MeasurementKind::kPoint);
  EXPECT_EQ(d.rows[1].axes, (std::array<bool, 3>{{false, false, true}}));
  EXPECT_DOUBLE_EQ(d.rows[1].p.z(), 0.3);
  EXPECT_EQ(d.rows[2].kind, MeasurementKind::kDistance);
  EXPECT_DOUBLE_EQ(d.rows[2].distance, 0.7005);
  EXPECT_EQ(d.rows[2].fixture, "P1");
  EXPECT_EQ(d.rows[3].kind, MeasurementKind::kPlane);
  EXPECT_EQ(d.rows[3].fixture, "table");
  EXPECT_EQ(d.rows[4].kind, MeasurementKind::kFixedPoint);
  EXPECT_EQ(d.rows[4].fixture, "socket");
  EXPECT_EQ(d.FixtureNames(MeasurementKind::kDistance), (std::vector<std::string>{"P1", "P2"}));
  EXPECT_EQ(d.FixtureNames(MeasurementKind::kPlane), std::vector<std::string>{"table"});
  EXPECT_TRUE(d.HasKind(MeasurementKind::kFixedPoint));
  EXPECT_FALSE(d.AllFullPoints());
  EXPECT_TRUE(d.SelectRows({0}).AllFullPoints());
  for (MeasurementKind k : {MeasurementKind::kPoint, MeasurementKind::kDistance, MeasurementKind::kPlane,
                            MeasurementKind::kFixedPoint}) {
    EXPECT_FALSE(MeasurementKindName(k).empty());
  }
  EXPECT_EQ(MeasurementKindName(MeasurementKind::kFixedPoint), "fixed_point");
}

TEST(DatasetKinds, AFileOfDistancesAloneNeedsNoPositionColumns) {
  const std::string text = "q1_rad,q2_rad,distance_m,pivot,split\n0.1,0.2,0.75,A,train\n0.3,0.4,0.5,B,test\n";
  const Dataset d = ParseDatasetCsv(text, "distances.csv");
  EXPECT_EQ(d.length_unit.name, "m");
  EXPECT_EQ(DatasetToCsv(d), text);
}

TEST(DatasetKinds, MethodsThatNeedPointsNameTheFirstOtherRow) {
  const Dataset d = ParseDatasetCsv("q1_deg,x_mm,y_mm,z_mm,distance_mm,pivot\n1,1,2,3,,\n2,,,,5,P\n", "d.csv");
  try {
    d.RequireFullPoints("geometric");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "d.csv:3: geometric needs point rows with x, y and z; row 2 is a distance");
  }
  EXPECT_NO_THROW(d.SelectRows({0}).RequireFullPoints("geometric"));
}

TEST(DatasetKinds, ValidateRefusesRowsMadeInCodeThatTheirKindCannotHold) {
  Dataset d;
  d.dof = 1;
  d.source = "made";
  Measurement m;
  m.q = Eigen::VectorXd::Zero(1);
  m.kind = MeasurementKind::kDistance;
  m.fixture = "P";
  m.distance = -1.0;
  d.rows = {m};
  EXPECT_THROW(d.Validate(1), std::invalid_argument);
  d.rows[0].distance = 1.0;
  EXPECT_NO_THROW(d.Validate(1));
  d.rows[0].fixture.clear();
  EXPECT_THROW(d.Validate(1), std::invalid_argument);
}

std::string KindErrorOf(const std::string& text) {
  try {
    ParseDatasetCsv(text, "data.csv").Validate(1);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

struct KindCase {
  const char* label;
  const char* text;
  const char* where;
  const char* what;
};
void PrintTo(const KindCase& c, std::ostream* os) { *os << c.label; }

class BadKinds : public ::testing::TestWithParam<KindCase> {};

TEST_P(BadKinds, NamesFileLineColumnAndReason) {
  const KindCase& c = GetParam();
  const std::string message = KindErrorOf(c.text);
  EXPECT_EQ(message.rfind(std::string(c.where) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(c.what), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

#define KINCAL_ROW(row) "q1_deg,x_mm,y_mm,z_mm,distance_mm,pivot,plane,point\n" row "\n"

INSTANTIATE_TEST_SUITE_P(
    Cases, BadKinds,
    ::testing::Values(
        KindCase{"distance_without_pivot", KINCAL_ROW("1,,,,700,,,"), "data.csv:2:6", "a distance row needs a pivot"},
        KindCase{"pivot_without_distance", KINCAL_ROW("1,,,,,P1,,"), "data.csv:2:7", "needs a distance (distance_mm)"},
        KindCase{"negative_distance", KINCAL_ROW("1,,,,-3,P1,,"), "data.csv:2:6", "expected a distance >= 0, got -3"},
        KindCase{"distance_with_coordinates", KINCAL_ROW("1,,5,,700,P1,,"), "data.csv:2:4",
                "a distance row (pivot 'P1') has no coordinates"},
        KindCase{"plane_with_coordinates", KINCAL_ROW("1,1,2,3,,,table,"), "data.csv:2:3",
                "a plane row (plane 'table') has no coordinates"},
        KindCase{"plane_with_distance", KINCAL_ROW("1,,,,5,,table,"), "data.csv:2:6", "has no distance"},
        KindCase{"point_with_coordinates", KINCAL_ROW("1,,,4,,,,socket"), "data.csv:2:5",
                "a fixed-point row (point 'socket') has no coordinates"},
        KindCase{"two_fixtures", KINCAL_ROW("1,,,,,,table,socket"), "data.csv:2:14",
                "names one fixture; this one names 'table' and 'socket'"},
        KindCase{"nothing_measured", KINCAL_ROW("1,,,,,,,"), "data.csv:2:1", "the row measures nothing"},
        KindCase{"distance_not_a_number", KINCAL_ROW("1,,,,far,P1,,"), "data.csv:2:6",
                "expected a finite number for a distance, got 'far'"},
        KindCase{"distance_column_alone", "q1_deg,distance_mm\n1,5\n", "data.csv:1:1",
                "a distance column (distance_mm or distance_m) and a pivot column together"},
        KindCase{"distance_unit_differs", "q1_deg,x_mm,y_mm,z_mm,distance_m,pivot\n1,1,2,3,,\n", "data.csv:1:23",
                "must be in the unit of x, y and z"},
        KindCase{"no_measurement_columns", "q1_deg,marker\n1,A\n", "data.csv:1:1", "expected position columns"},
        KindCase{"orientation_of_partial_point", "q1_deg,x_mm,y_mm,z_mm,qw,qx,qy,qz\n1,1,,3,1,0,0,0\n",
                "data.csv:2:8", "an orientation needs x, y and z"},
        KindCase{"orientation_partly_given", "q1_deg,x_mm,y_mm,z_mm,qw,qx,qy,qz\n1,1,2,3,1,,0,0\n", "data.csv:2:9",
                "every cell of qw, qx, qy, qz filled, or none"},
        KindCase{"orientation_of_a_plane_row",
                "q1_deg,x_mm,y_mm,z_mm,plane,qw,qx,qy,qz\n1,,,,t,1,0,0,0\n", "data.csv:2:8", "has no orientation"}),
    [](const ::testing::TestParamInfo<KindCase>& info) { return std::string(info.param.label); });

}  // namespace
}  // namespace kincal
