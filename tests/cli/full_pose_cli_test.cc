// `kincal identify` on full-pose data (position and orientation rows): the held-out orientation error is
// printed and reported beside the position error, and the report gives the orientation weight used.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

const std::string kNominal = SourcePath("examples/robots/seed_nominal.yaml");
const std::string kTruth = SourcePath("examples/robots/seed_identified.yaml");

std::string SimulateFullPose(const TempDir& tmp, const std::string& name, int seed) {
  const std::string path = tmp.path(name);
  const CommandResult r = RunKincal("simulate --nominal " + kNominal + " --truth " + kTruth +
                                    " --protocol random --poses 60 --noise 10um --orientation --seed " +
                                    std::to_string(seed) + " --out " + path);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return path;
}

nlohmann::json Identify(const TempDir& tmp, const std::string& options, CommandResult* r) {
  WriteText(tmp.path("options.yaml"), options);
  *r = RunKincal("identify --nominal " + kNominal + " --data " + SimulateFullPose(tmp, "train.csv", 1) +
                 " --validate " + SimulateFullPose(tmp, "test.csv", 2) + " --method least_squares --options " +
                 tmp.path("options.yaml") + " --out " + tmp.path("id.yaml") + " --report " + tmp.path("report.json"));
  if (r->exit_code != 0) return nlohmann::json();
  return nlohmann::json::parse(ReadText(tmp.path("report.json")));
}

TEST(FullPoseCli, ReportsTheOrientationErrorAndItsWeight) {
  TempDir tmp;
  CommandResult r;
  const nlohmann::json report = Identify(tmp, "orientation_length: 0.25\n", &r);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("held-out (60 rows with orientation): orientation error"), std::string::npos) << r.out;
  EXPECT_EQ(report["stages"][0]["details"]["orientation_length_m_per_rad"].get<double>(), 0.25);
  const auto& orientation = report["validation"]["orientation"];
  EXPECT_EQ(orientation["unit"], "mrad");
  EXPECT_EQ(orientation["identified"]["count"].get<int>(), 60);
  // The simulated orientations are exact: the identified robot predicts them to the position noise's
  // effect on the fit (well under a milliradian).
  EXPECT_LT(orientation["identified"]["rms"].get<double>(), 0.1);
  EXPECT_GT(orientation["identified"]["rms"].get<double>(), 0.0);
}

TEST(FullPoseCli, PositionOnlyDataHasNoOrientationLines) {
  TempDir tmp;
  const std::string train = tmp.path("train.csv");
  ASSERT_EQ(RunKincal("simulate --nominal " + kNominal + " --truth " + kTruth +
                      " --protocol random --poses 60 --noise 10um --seed 3 --out " + train)
                .exit_code,
            0);
  const CommandResult r =
      RunKincal("identify --nominal " + kNominal + " --data " + train + " --validate " + train +
                " --method least_squares --out " + tmp.path("id.yaml") + " --report " + tmp.path("report.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("orientation error"), std::string::npos) << r.out;
  const nlohmann::json report = nlohmann::json::parse(ReadText(tmp.path("report.json")));
  EXPECT_FALSE(report["validation"].contains("orientation"));
  EXPECT_FALSE(report["stages"][0]["details"].contains("orientation_length_m_per_rad"));
}

}  // namespace
}  // namespace kincal::testing
