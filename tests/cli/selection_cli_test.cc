// identify --select and predict --report on the command line: the selection table in the printed summary
// and the report, the chosen model's terms alone in the identified robot (here none: the truth has no joint
// errors), and every predicted row's sd_mm (positive, a few um for 150 poses with 20 um noise): the
// parameters' part sd_param_mm and the model inadequacy tau of the report (prediction_uncertainty.h (2));
// a report from before tau (no inadequacy_m) reads as tau = 0; a report without a covariance: exit 2.
// The same on distance rows, plane contacts and a file mixing them with points: the CV table finite, the
// chosen candidate scored, --validate scoring held-out rows in their own kind, and predict's error the row's
// residual in its kind from its predicted point and the identified fixtures.
#include <algorithm>
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "framework/csv.h"
#include "robot/robot_file.h"
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

// The rows of several CSV datasets in one file: the union of their columns, each row filling its own.
std::string MergedCsv(const std::vector<std::string>& paths) {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (const std::string& path : paths) {
    const CsvTable t = ParseCsv(testing::ReadText(path), path);
    for (const std::string& c : t.header.cells) {
      if (std::find(header.begin(), header.end(), c) == header.end()) header.push_back(c);
    }
    for (const CsvRow& row : t.rows) {
      std::map<std::string, std::string>& out = rows.emplace_back();
      for (size_t k = 0; k < row.cells.size(); ++k) out[t.header.cells[k]] = row.cells[k];
    }
  }
  std::string text;
  for (size_t k = 0; k < header.size(); ++k) text += (k ? "," : "") + header[k];
  for (auto& row : rows) {
    text += "\n";
    for (size_t k = 0; k < header.size(); ++k) text += (k ? "," : "") + row[header[k]];
  }
  return text + "\n";
}

double Cell(const CsvTable& t, const CsvRow& row, const std::string& column) {
  const std::string& cell = row.cells.at(FindColumn(t, column));
  return cell.empty() ? NAN : std::stod(cell);
}

// A truth IRB 120 standing where irb120_placed.yaml does, with three pivots and three planes it reaches.
const char* kInstrumentFixtures =
    "fixtures:\n"
    "  pivots: {P1: {xyz: [955, -163, -133]}, P2: {xyz: [2112, -26, -99]}, P3: {xyz: [1428, 874, -23]}}\n"
    "  planes: {plane1: {normal: [0, 0, -1], offset: -602}, plane2: {normal: [-1, 0, 0], offset: -1160},\n"
    "           plane3: {normal: [0, 1, 0], offset: 80}}\n";

TEST(SelectionCli, DistancesPlanesAndMixedRowsSelectValidateAndPredictInTheirKind) {
  TempDir dir;
  const std::string placed = SourcePath("examples/robots/irb120_placed.yaml");
  testing::WriteText(dir.path("truth.yaml"),
                     testing::ReadText(SourcePath("examples/robots/irb120_as_measured.yaml")) + kInstrumentFixtures);
  testing::WriteText(dir.path("declared.yaml"), testing::ReadText(placed) +
                                                    "velocity_limits: [250, 250, 250, 320, 320, 420]\n"
                                                    "joint_errors:\n  - {joint: 2, type: gravity}\n");
  // Training rows (seed 1) and held-out rows (seed 5) of each instrument, 10 um along what it reads.
  for (const char* instrument : {"point", "distance", "plane"}) {
    for (const auto& [seed, poses] : {std::pair<int, int>{1, 90}, {5, 30}}) {
      const auto r = RunKincal("simulate --nominal " + placed + " --truth " + dir.path("truth.yaml") +
                               " --protocol random --instrument " + instrument + " --poses " + std::to_string(poses) +
                               " --noise 10um --seed " + std::to_string(seed) + " --out " +
                               dir.path(std::string(instrument) + std::to_string(seed) + ".csv"));
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
  }
  for (const char* seed : {"1", "5"}) {
    testing::WriteText(dir.path(std::string("mixed") + seed + ".csv"),
                       MergedCsv({dir.path(std::string("point") + seed + ".csv"),
                                  dir.path(std::string("distance") + seed + ".csv"),
                                  dir.path(std::string("plane") + seed + ".csv")}));
  }
  for (const std::string kind : {"distance", "plane", "mixed"}) {
    SCOPED_TRACE(kind);
    auto r = RunKincal("identify --no-check --nominal " + dir.path("declared.yaml") + " --data " +
                       dir.path(kind + "1.csv") + " --method least_squares --select --validate " +
                       dir.path(kind + "5.csv") + " --out " + dir.path(kind + ".yaml") + " --report " +
                       dir.path(kind + ".json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("+ gravity 2"), std::string::npos) << r.out;
    const nlohmann::json report = nlohmann::json::parse(testing::ReadText(dir.path(kind + ".json")));
    const nlohmann::json& details = report.at("stages").back().at("details");
    int chosen = 0;
    for (const auto& c : details.at("selection").at("candidates")) {
      EXPECT_TRUE(std::isfinite(c.at("cv_rms_mm").get<double>())) << c.dump();
      EXPECT_TRUE(std::isfinite(c.at("se_mm").get<double>())) << c.dump();
      EXPECT_LT(c.at("cv_rms_mm").get<double>(), 0.05) << c.dump();  // 10 um rows: tens of um at most
      chosen += c.at("chosen").get<bool>();
    }
    EXPECT_EQ(chosen, 1);
    const double tau_mm = details.at("prediction_covariance").at("inadequacy_m").get<double>() * 1e3;
    EXPECT_TRUE(tau_mm >= 0.0 && tau_mm < 0.05) << tau_mm;
    // Held-out rows in their own kind: the identified arm about the noise, the registered nominal far worse.
    const nlohmann::json& validation = report.at("validation");
    EXPECT_EQ(validation.at("identified").at("count").get<int>(), kind == "mixed" ? 90 : 30);
    EXPECT_LT(validation.at("identified").at("rms").get<double>(), 0.05);
    EXPECT_GT(validation.at("nominal").at("rms").get<double>(), 0.2);
    EXPECT_TRUE(std::isfinite(validation.at("nominal_unregistered").at("rms").get<double>()));

    r = RunKincal("predict --robot " + dir.path(kind + ".yaml") + " --data " + dir.path(kind + "5.csv") + " --out " +
                  dir.path(kind + "_p.csv"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Robot identified = ReadRobotFile(dir.path(kind + ".yaml"));
    const CsvTable data = ParseCsv(testing::ReadText(dir.path(kind + "5.csv")), "data");
    const CsvTable p = ParseCsv(testing::ReadText(dir.path(kind + "_p.csv")), "p");
    ASSERT_EQ(p.rows.size(), data.rows.size());
    std::map<std::string, int> signs;  // distance and plane errors are signed: the noise gives both
    for (size_t i = 0; i < p.rows.size(); ++i) {
      const auto given = [&](const char* column) {
        const int c = FindColumn(data, column);
        return c >= 0 && !data.rows[i].cells[c].empty() ? data.rows[i].cells[c] : std::string();
      };
      const Eigen::Vector3d at = 1e-3 * Eigen::Vector3d(Cell(p, p.rows[i], "x_mm"), Cell(p, p.rows[i], "y_mm"),
                                                         Cell(p, p.rows[i], "z_mm"));
      const double error = Cell(p, p.rows[i], "error_mm") * 1e-3;
      double expected = NAN;
      if (!given("pivot").empty()) {
        const Fixture* f = identified.fixtures.Find(Fixture::Type::kPivot, given("pivot"));
        ASSERT_NE(f, nullptr) << given("pivot");
        expected = (at - f->position).norm() - 1e-3 * std::stod(given("distance_mm"));
        EXPECT_TRUE(std::isnan(Cell(p, p.rows[i], "dx_mm")));
        ++signs[std::string("distance") + (error > 0 ? "+" : "-")];
      } else if (!given("plane").empty()) {
        const Fixture* f = identified.fixtures.Find(Fixture::Type::kPlane, given("plane"));
        ASSERT_NE(f, nullptr) << given("plane");
        expected = f->normal.dot(at) - f->offset;
        ++signs[std::string("plane") + (error > 0 ? "+" : "-")];
      } else {
        const Eigen::Vector3d measured(std::stod(given("x_mm")), std::stod(given("y_mm")), std::stod(given("z_mm")));
        expected = (at - 1e-3 * measured).norm();
        EXPECT_NEAR(Cell(p, p.rows[i], "dx_mm"), 1e3 * at.x() - measured.x(), 1e-6);
      }
      EXPECT_NEAR(error, expected, 1e-9) << "row " << i + 1;
      EXPECT_LT(std::abs(error), 1e-4) << "row " << i + 1;  // 10 um rows: the identified arm fits them
    }
    for (const char* sign : {"+", "-"}) {
      if (kind != "plane") {
        EXPECT_GT(signs[std::string("distance") + sign], 0) << sign;
      }
      if (kind != "distance") {
        EXPECT_GT(signs[std::string("plane") + sign], 0) << sign;
      }
    }
  }
}

}  // namespace
}  // namespace kincal
