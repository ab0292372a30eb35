// The calibration doctor (doctor/doctor.h) on the project's real datasets as their own tests read them
// (each skips without ../shared/data, and fails instead under KINCAL_REQUIRE_DATA=1): the clean originals
// give no finding, and ur10_ipa2021 series D with its radian joint values under degree headers is found as
// an angle unit, by `kincal check` and by `kincal identify` before it fits.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "doctor/doctor.h"
#include "robot/robot_file.h"
#include "tests/estimators/geometric/fanuc_fixture.h"
#include "tests/estimators/irb120_faro.h"
#include "tests/estimators/irb120_wu2015.h"
#include "tests/real_data/ur10_ipa2021_util.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

std::string Lines(const std::vector<doctor::Finding>& findings) {
  std::string out;
  for (const auto& f : findings) out += doctor::FindingLine(f) + "\n";
  return out;
}

void ExpectNoFinding(const Robot& robot, const Dataset& data, const std::string& name) {
  const std::vector<doctor::Finding> findings = doctor::Diagnose(robot, data);
  EXPECT_TRUE(findings.empty()) << name << ":\n" << Lines(findings);
}

TEST(DoctorRealData, Ur10SeriesAToDGiveNoFinding) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  for (const char* series : {kUr10A, kUr10B, kUr10C, kUr10D}) {
    ASSERT_EQ(RunUr10Converter("'" + Ur10Series(series) + "' --out '" + dir.path("s.csv") + "'", dir, nullptr), 0);
    ExpectNoFinding(LoadExampleRobot("ur10_dh.yaml"), ReadDataset(dir.path("s.csv")), series);
  }
}

TEST(DoctorRealData, Irb120FaroGivesNoFinding) {
  Dataset smr1, smr123;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120Faro(SharedDataPath("irb120_faro"), 1, &smr1),
                                  "no ../shared/data/irb120_faro");
  ExpectNoFinding(Irb120FaroNominal(), smr1, "reflector 1");
  ASSERT_TRUE(LoadIrb120FaroReflectors(SharedDataPath("irb120_faro"), {1, 2, 3}, &smr123));
  Robot three = Irb120FaroNominal();  // where the reflectors are is not known: the markers start at the flange
  for (const std::string id : {"SMR1", "SMR2", "SMR3"}) three.markers[id] = Eigen::Vector3d::Zero();
  ExpectNoFinding(three, smr123, "reflectors 1-3");
}

TEST(DoctorRealData, Irb120Wu2015GivesNoFinding) {
  Irb120Wu2015 wu;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120Wu2015(SharedDataPath("irb120_wu2015"), &wu),
                                  "no ../shared/data/irb120_wu2015");
  Robot nominal = LoadExampleRobot("irb120_mdh.yaml");
  for (const std::string id : {"p1", "p2", "p3"}) nominal.markers[id] = Eigen::Vector3d::Zero();
  ExpectNoFinding(nominal, wu.calibration, "calibration points");
}

TEST(DoctorRealData, FanucSweepsGiveNoFinding) {
  std::string csv;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(FanucSweepsCsv(SharedDataPath("fanuc_boby2021/sweeps.csv"), false, &csv),
                                  "no ../shared/data/fanuc_boby2021");
  ExpectNoFinding(LoadExampleRobot("fanuc_r2000_nominal.yaml"), ParseDatasetCsv(csv, "sweeps.csv"), "sweeps");
}

// Series D's joint values are radians; under q1_deg.. headers they are read as degrees.
TEST(DoctorRealData, Ur10SeriesDRadiansUnderDegreeHeadersAreAnAngleUnit) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  ASSERT_EQ(RunUr10Converter("'" + Ur10Series(kUr10D) + "' --out '" + dir.path("d.csv") + "'", dir, nullptr), 0);
  std::string text = ReadText(dir.path("d.csv"));
  for (size_t at; (at = text.find("_rad,")) != std::string::npos;) text.replace(at, 5, "_deg,");
  WriteText(dir.path("d_deg.csv"), text);
  const std::string robot = SourcePath("examples/robots/ur10_dh.yaml");
  const CommandResult check = RunKincal("check --nominal '" + robot + "' --data '" + dir.path("d_deg.csv") +
                                        "' --report '" + dir.path("check.json") + "'");
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir.path("check.json")));
  ASSERT_EQ(report["findings"].size(), 1u) << check.out;
  EXPECT_EQ(report["findings"][0]["cause"], "angle_unit");
  EXPECT_LT(report["findings"][0]["rms_repaired_mm"].get<double>(),
            0.1 * report["findings"][0]["rms_as_given_mm"].get<double>());
  const CommandResult identify = RunKincal("identify --nominal '" + robot + "' --data '" + dir.path("d_deg.csv") +
                                           "' --method least_squares --out '" + dir.path("i.yaml") + "'");
  EXPECT_NE(identify.err.find("warning: check: angle_unit: "), std::string::npos) << identify.err;
}

}  // namespace
}  // namespace kincal::testing
