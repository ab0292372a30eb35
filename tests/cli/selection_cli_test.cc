// identify --select and predict --report on the command line: the selection table in the printed summary
// and the report, the chosen model's terms alone in the identified robot (here none: the truth has no joint
// errors), and every predicted row's sd_mm (positive, a few um for 150 poses with 20 um noise): the
// parameters' part sd_param_mm and the model inadequacy tau of the report (prediction_uncertainty.h (2));
// a report from before tau (no inadequacy_m) reads as tau = 0; a report without a covariance: exit 2.
#include <cmath>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "framework/csv.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;
using testing::TempDir;

TEST(SelectionCli, SelectsPrintsTheTableAndPredictGivesSd) {
  TempDir dir;
  const std::string nominal = SourcePath("examples/robots/seed_nominal.yaml");
  // The nominal robot with joint-error terms the truth (the seed's identified arm) does not have.
  std::string text = testing::ReadText(nominal);
  text +=
      "velocity_limits: [250, 250, 250, 320, 320, 420]\njoint_errors:\n"
      "  - {joint: 2, type: gravity}\n  - {joint: 1, type: backlash}\n";
  testing::WriteText(dir.path("declared.yaml"), text);
  auto r =
      RunKincal("simulate --nominal " + nominal + " --truth " + SourcePath("examples/robots/seed_identified.yaml") +
                " --protocol random --poses 150 --noise 20um --seed 4 --out " + dir.path("data.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunKincal("identify --nominal " + dir.path("declared.yaml") + " --data " + dir.path("data.csv") +
                " --method least_squares --select --out " + dir.path("id.yaml") + " --report " + dir.path("r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("model selection, 5-fold blocked CV"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("+ gravity 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("selected model: geometry"), std::string::npos) << r.out;  // nothing beyond geometry
  EXPECT_EQ(testing::ReadText(dir.path("id.yaml")).find("joint_errors"), std::string::npos);
  const std::string report = testing::ReadText(dir.path("r.json"));
  EXPECT_NE(report.find("\"selection\""), std::string::npos);
  EXPECT_NE(report.find("\"prediction_covariance\""), std::string::npos);
  EXPECT_NE(r.out.find("model inadequacy tau (cross-validation of the selection)"), std::string::npos) << r.out;
  nlohmann::json json = nlohmann::json::parse(report);
  nlohmann::json* covariance = nullptr;
  for (auto& stage : json.at("stages"))
    if (stage.at("details").contains("prediction_covariance")) covariance = &stage["details"]["prediction_covariance"];
  ASSERT_NE(covariance, nullptr);
  const double tau_mm = covariance->at("inadequacy_m").get<double>() * 1e3;
  EXPECT_GE(tau_mm, 0.0);
  EXPECT_LT(tau_mm, 0.05);  // the right model (the truth has no joint errors): tau about the noise or less

  r = RunKincal("predict --robot " + dir.path("id.yaml") + " --nominal " + nominal + " --data " + dir.path("data.csv") +
                " --report " + dir.path("r.json") + " --out " + dir.path("p.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = ParseCsv(testing::ReadText(dir.path("p.csv")), "p.csv");
  ASSERT_EQ(t.rows.size(), 150u);
  ASSERT_GE(t.header.cells.size(), 2u);
  EXPECT_EQ(t.header.cells[t.header.cells.size() - 3], "sd_param_mm");
  EXPECT_EQ(t.header.cells[t.header.cells.size() - 2], "sd_mm");
  EXPECT_EQ(t.header.cells.back(), "outside_support");
  for (const auto& row : t.rows) {
    const double sd_param = std::stod(row.cells[row.cells.size() - 3]), sd = std::stod(row.cells[row.cells.size() - 2]);
    EXPECT_GT(sd_param, 0.0);
    EXPECT_LT(sd_param, 0.05);  // 150 poses with 20 um noise: a few um
    // The training rows themselves: within the joint range, so (2) with the report's tau.
    EXPECT_NEAR(sd, std::sqrt(sd_param * sd_param + tau_mm * tau_mm), 1e-6 + 1e-6 * sd);
  }

  // A report written before tau: sd_mm is the parameters' part.
  covariance->erase("inadequacy_m");
  covariance->erase("inadequacy_beyond_m");
  covariance->erase("inadequacy_source");
  testing::WriteText(dir.path("old.json"), json.dump());
  r = RunKincal("predict --robot " + dir.path("id.yaml") + " --nominal " + nominal + " --data " + dir.path("data.csv") +
                " --report " + dir.path("old.json") + " --out " + dir.path("p_old.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("sd_mm is the parameters' part only"), std::string::npos) << r.out;
  const CsvTable old = ParseCsv(testing::ReadText(dir.path("p_old.csv")), "p_old.csv");
  ASSERT_EQ(old.rows.size(), 150u);
  for (const auto& row : old.rows) EXPECT_EQ(row.cells[row.cells.size() - 3], row.cells[row.cells.size() - 2]);

  testing::WriteText(dir.path("bad.json"), "{\"stages\": [{\"details\": {}}]}\n");
  r = RunKincal("predict --robot " + dir.path("id.yaml") + " --data " + dir.path("data.csv") + " --report " +
                dir.path("bad.json") + " --out " + dir.path("p2.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("prediction_covariance"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace kincal
