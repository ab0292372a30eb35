// The study report's priors and weak parameters: the numbers an error-model fit with `prior: on` gives per
// parameter (prior sd, posterior sd, the data's sd and share, weak) reach parameters.csv and report.md, in
// report units, for the fits that have them only.
#include <cmath>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "framework/dataset.h"
#include "studies/results_files.h"
#include "studies/runner.h"
#include "tests/studies/study_test_util.h"

namespace kincal {
namespace {

using testing::ReadText;
using testing::TempDir;

// The cells of the report.md table row that starts with `first` cells (trimmed), or empty.
std::vector<std::string> ReportRow(const std::string& report, const std::vector<std::string>& first) {
  std::istringstream lines(report);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("|", 0) != 0) continue;
    std::vector<std::string> cells;
    std::istringstream parts(line.substr(1));
    for (std::string cell; std::getline(parts, cell, '|');) {
      cell.erase(0, cell.find_first_not_of(' '));
      cell.erase(cell.find_last_not_of(' ') + 1);
      cells.push_back(cell);
    }
    if (cells.size() >= first.size() && std::equal(first.begin(), first.end(), cells.begin())) return cells;
  }
  return {};
}

double Relative(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

TEST(StudyPriorsTest, ReportCarriesTheEstimatorsPriorColumns) {
  TempDir tmp;
  Dataset simulated = testing::SeedMeasurements(30, 20e-6, 3);
  for (size_t i = 0; i < simulated.rows.size(); ++i)
    simulated.rows[i].split = i % 4 == 3 ? Split::kTest : Split::kTrain;
  WriteDataset(simulated, tmp.path("measured.csv"));
  const std::string nominal_path = testing::SourcePath("examples/robots/seed_nominal.yaml");
  const Study study = ParseStudy("name: priors\nrobots: {nominal: " + nominal_path +
                                     "}\ndatasets:\n  - {name: tracker, file: measured.csv}\n"
                                     "estimators:\n  - least_squares\n"
                                     "  - {name: map, method: least_squares, options: {prior: on}}\n",
                                 tmp.path("priors.yaml"));
  RunStudy(study, tmp.path("out"), StudyRunOptions());

  // The same fit, outside the study: the study's training rows are the file's train rows.
  const Robot nominal = ReadRobotFile(nominal_path);
  const Dataset train = ReadDataset(tmp.path("measured.csv")).Subset(Split::kTrain);
  Robot identified;
  const EstimationReport report =
      Estimators().Create("least_squares", YAML::Load("{prior: on}"))->Estimate(nominal, nominal, train, &identified);

  const ResultTable t = ReadResultTable(tmp.path("out") + "/parameters.csv");
  const auto cell = [&](const std::string& estimator, const std::string& name, const std::string& column) {
    for (const auto& row : t.rows) {
      if (row[t.Column("estimator")] == estimator && row[t.Column("parameter")] == name) return row[t.Column(column)];
    }
    ADD_FAILURE() << "no row " << estimator << " " << name;
    return std::string();
  };
  const std::string md = ReadText(tmp.path("out") + "/report.md");
  ASSERT_NE(md.find("Priors and weak parameters"), std::string::npos);
  // A weak parameter's partners, as the fit's details name them (estimators/error_model/weak_parameters.h).
  std::map<std::string, std::string> partners;
  for (const auto& w : report.details.at("weak_parameters")) {
    for (const auto& partner : w.at("trades_against")) {
      std::string& list = partners[w.at("name").get<std::string>()];
      list += (list.empty() ? "" : " ") + partner.get<std::string>();
    }
  }
  int lengths = 0, angles = 0, report_rows = 0, weak = 0;
  for (const ParameterEstimate& p : report.parameters) {
    if (!p.free || !(p.prior_sd > 0.0) || (p.unit != "m" && p.unit != "rad")) continue;
    const double scale = p.unit == "m" ? 1e3 : 180.0 / M_PI;  // report units: mm, deg
    (p.unit == "m" ? lengths : angles)++;
    EXPECT_LT(Relative(std::stod(cell("map", p.name, "prior_sd")), p.prior_sd * scale), 1e-3) << p.name;
    EXPECT_LT(Relative(std::stod(cell("map", p.name, "stddev")), p.stddev * scale), 1e-3) << p.name;
    EXPECT_LT(Relative(std::stod(cell("map", p.name, "data_sd")), p.data_sd * scale), 1e-3) << p.name;
    EXPECT_LT(std::abs(std::stod(cell("map", p.name, "data_share")) - p.data_share), 1e-3) << p.name;
    EXPECT_EQ(cell("map", p.name, "weak"), p.weak ? "1" : "0") << p.name;
    EXPECT_EQ(cell("map", p.name, "trades_against"), p.weak ? partners[p.name] : "") << p.name;
    // The fit without a prior has none.
    EXPECT_EQ(cell("least_squares", p.name, "prior_sd"), "") << p.name;

    // report.md: the row of (parameter, unit, estimator) holds the same numbers, as the report writes them.
    const std::vector<std::string> row = ReportRow(md, {p.name, p.unit == "m" ? "mm" : "deg", "map"});
    if (row.empty()) continue;  // a parameter no estimator moved is not in the report's tables
    ASSERT_EQ(row.size(), 8u) << p.name;
    ++report_rows;
    EXPECT_LT(Relative(std::stod(row[3]), p.prior_sd * scale), 1e-2) << p.name;
    EXPECT_LT(Relative(std::stod(row[4]), p.stddev * scale), 1e-2) << p.name;
    EXPECT_LT(Relative(std::stod(row[5]), p.data_sd * scale), 1e-2) << p.name;
    EXPECT_LT(std::abs(std::stod(row[6]) - p.data_share), 2e-3) << p.name;
    EXPECT_EQ(row[7] == "–", !p.weak) << p.name;
    if (p.weak) {
      ++weak;
      EXPECT_EQ(row[7], "1/1 trials, trades against " + partners[p.name]) << p.name;
    }
    EXPECT_TRUE(ReportRow(md, {p.name, p.unit == "m" ? "mm" : "deg", "least_squares"}).empty()) << p.name;
  }
  // The seed arm's lengths have the 1 mm prior, its angles 2 mrad (docs/guide/methods.md, Priors and weak parameters).
  EXPECT_GT(lengths, 0);
  EXPECT_GT(angles, 0);
  EXPECT_GT(report_rows, 0);
  // 30 random poses of the seed arm leave the wrist's offsets trading against each other: weak, held by
  // their priors.
  EXPECT_GT(weak, 0);
}

}  // namespace
}  // namespace kincal
