// Running studies: determinism, shards merged equal an unsharded run, the scoring of known methods, failures
// as statuses, measured data, sensitivity sweeps.
#include <regex>

#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "robot/simulator.h"
#include "studies/report.h"
#include "studies/results_files.h"
#include "studies/runner.h"
#include "tests/studies/study_test_util.h"
#include "tests/studies/test_methods.h"

namespace kincal {
namespace {

using testing::kDeterministicFiles;
using testing::ReadText;
using testing::ReportWithoutTimes;
using testing::TempDir;

class StudyRunTest : public ::testing::Test {
 protected:
  StudyRunTest()
      : registries_(testing::MakeTestRegistries(testing::SeedTruth())),
        study_(ParseStudy(testing::SmallStudyYaml(), "small.yaml", registries_.view())) {}

  void Run(const std::string& dir, int threads, int shard = 1, int shards = 1) {
    StudyRunOptions o;
    o.threads = threads;
    o.shard_index = shard;
    o.shard_count = shards;
    RunStudy(study_, dir, o, registries_.view());
  }

  // The rows of results.csv of one (dataset, estimator, compensator, validation), as maps column -> cell.
  std::vector<std::map<std::string, std::string>> Rows(const std::string& dir, const std::string& dataset,
                                                       const std::string& estimator, const std::string& compensator,
                                                       const std::string& validation) {
    const ResultTable t = ReadResultTable(dir + "/results.csv");
    std::vector<std::map<std::string, std::string>> out;
    for (const auto& row : t.rows) {
      std::map<std::string, std::string> m;
      for (size_t i = 0; i < t.header.size(); ++i) m[t.header[i]] = row[i];
      if (m["dataset"] == dataset && m["estimator"] == estimator && m["compensator"] == compensator &&
          m["validation"] == validation) {
        out.push_back(m);
      }
    }
    return out;
  }

  testing::TestRegistries registries_;
  Study study_;
};

double Number(const std::string& text) { return std::stod(text); }

TEST_F(StudyRunTest, SameStudyTwiceGivesTheSameBytesWhateverTheThreads) {
  TempDir tmp;
  Run(tmp.path("a"), 1);
  Run(tmp.path("b"), 3);
  for (const char* file : kDeterministicFiles) {
    SCOPED_TRACE(file);
    const std::string a = ReadText(tmp.path("a") + "/" + file);
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, ReadText(tmp.path("b") + "/" + file));
  }
  EXPECT_EQ(ReportWithoutTimes(tmp.path("a")), ReportWithoutTimes(tmp.path("b")));
  // timings.csv has the same keys, one row per results row.
  EXPECT_EQ(ReadResultTable(tmp.path("a") + "/timings.csv").rows.size(),
            ReadResultTable(tmp.path("a") + "/results.csv").rows.size());
}

TEST_F(StudyRunTest, ShardsMergedEqualTheUnshardedRun) {
  TempDir tmp;
  Run(tmp.path("whole"), 2);
  for (int shards : {2, 3}) {
    SCOPED_TRACE(shards);
    std::vector<std::string> dirs;
    for (int i = shards; i >= 1; --i) {  // any order
      dirs.push_back(tmp.path("s" + std::to_string(shards) + "_" + std::to_string(i)));
      Run(dirs.back(), 1, i, shards);
      EXPECT_FALSE(std::filesystem::exists(dirs.back() + "/report.md"));
    }
    const std::string merged = tmp.path("merged" + std::to_string(shards));
    MergeShards(dirs, merged);
    WriteReport(merged);
    for (const char* file : kDeterministicFiles) {
      SCOPED_TRACE(file);
      EXPECT_EQ(ReadText(merged + "/" + file), ReadText(tmp.path("whole") + "/" + file));
    }
    EXPECT_EQ(ReportWithoutTimes(merged), ReportWithoutTimes(tmp.path("whole")));
  }
}

TEST_F(StudyRunTest, MergeRefusesIncompleteOrForeignShards) {
  TempDir tmp;
  Run(tmp.path("s1"), 1, 1, 2);
  Run(tmp.path("s2"), 1, 2, 2);
  EXPECT_THROW(MergeShards({tmp.path("s1")}, tmp.path("m")), std::invalid_argument);
  EXPECT_THROW(MergeShards({tmp.path("s1"), tmp.path("s1")}, tmp.path("m")), std::invalid_argument);
  study_.seed = 8;  // another study
  Run(tmp.path("other2"), 1, 2, 2);
  EXPECT_THROW(MergeShards({tmp.path("s1"), tmp.path("other2")}, tmp.path("m")), std::invalid_argument);
  EXPECT_NO_THROW(MergeShards({tmp.path("s2"), tmp.path("s1")}, tmp.path("m")));
  // A shard folder alone is not a report.
  EXPECT_THROW(WriteReport(tmp.path("s1")), std::invalid_argument);
}

// The scoring: with the true robot identified, a converging compensator reaches the targets on the real arm
// to the encoders' resolution, while the nominal commands miss them by millimetres (the seed's arm).
TEST_F(StudyRunTest, OracleWithCompensationReachesTheTargets) {
  TempDir tmp;
  Run(tmp.path("r"), 2);
  auto before = Rows(tmp.path("r"), "random", "none", "none", "targets");
  auto model = Rows(tmp.path("r"), "random", "oracle", "-", "targets");
  auto after = Rows(tmp.path("r"), "random", "oracle", "jacobian_ik", "targets");
  ASSERT_EQ(before.size(), 2u);  // two trials
  ASSERT_EQ(after.size(), 2u);
  for (int t = 0; t < 2; ++t) {
    EXPECT_GT(Number(before[t]["position_error_mean_mm"]), 1.0);
    EXPECT_GT(Number(before[t]["orientation_error_mean_deg"]), 0.1);
    // The oracle predicts the arm exactly (same encoder counts on both sides).
    EXPECT_LT(Number(model[t]["position_error_max_mm"]), 1e-9);
    // Motor counts are integers: 2048 per motor turn, ratios ~4000-8000, so about 1e-6 rad per joint.
    EXPECT_LT(Number(after[t]["position_error_max_mm"]), 5e-3);
    EXPECT_LT(Number(after[t]["orientation_error_max_deg"]), 5e-4);
    EXPECT_EQ(after[t]["status"], "ok");
    EXPECT_EQ(after[t]["converged"], "12");
  }
  // Same targets, same commands, same data for both trials of the baseline.
  EXPECT_EQ(before[0]["position_error_mean_mm"], before[1]["position_error_mean_mm"]);
  // The oracle's parameters are the truth.
  const ResultTable p = ReadResultTable(tmp.path("r") + "/parameters.csv");
  int oracle_rows = 0;
  for (size_t r = 0; r < p.rows.size(); ++r) {
    if (p.Text(r, p.Column("estimator")) != "oracle") continue;
    ++oracle_rows;
    EXPECT_EQ(p.Number(r, p.Column("error")), 0.0) << p.Text(r, p.Column("parameter"));
  }
  const Robot truth = testing::SeedTruth();
  EXPECT_EQ(oracle_rows, 2 * (truth.model().num_parameters() + truth.dof()));  // two trials x (geometry + ratios)
}

TEST_F(StudyRunTest, ConvergenceAndIsoResults) {
  TempDir tmp;
  Run(tmp.path("r"), 2);
  const ResultTable c = ReadResultTable(tmp.path("r") + "/convergence.csv");
  double first = 0.0, last = 1.0;
  int rows = 0;
  for (size_t r = 0; r < c.rows.size(); ++r) {
    if (c.Text(r, c.Column("estimator")) != "oracle" || c.Text(r, c.Column("trial")) != "0") continue;
    EXPECT_EQ(c.Text(r, c.Column("compensator")), "jacobian_ik");
    const double v = c.Number(r, c.Column("position_error_median_mm"));
    if (c.Text(r, c.Column("iteration")) == "0") first = v;
    last = v;
    ++rows;
  }
  EXPECT_GE(rows, 2);
  EXPECT_GT(first, 1.0);  // mm: the seed's errors before the first step
  EXPECT_LT(last, 1e-9);  // to round-off

  const ResultTable iso = ReadResultTable(tmp.path("r") + "/iso9283.csv");
  std::map<std::string, std::vector<size_t>> by_method;
  for (size_t r = 0; r < iso.rows.size(); ++r) {
    if (iso.Text(r, iso.Column("dataset")) == "random" && iso.Text(r, iso.Column("trial")) == "0") {
      by_method[iso.Text(r, iso.Column("estimator")) + "/" + iso.Text(r, iso.Column("compensator"))].push_back(r);
    }
  }
  ASSERT_EQ(by_method["none/none"].size(), 5u);  // P1..P5
  ASSERT_EQ(by_method["oracle/jacobian_ik"].size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const size_t b = by_method["none/none"][k], a = by_method["oracle/jacobian_ik"][k];
    EXPECT_EQ(iso.Text(a, iso.Column("pose")), "P" + std::to_string(k + 1));
    EXPECT_EQ(iso.Text(a, iso.Column("cycles")), "6");
    EXPECT_GT(iso.Number(b, iso.Column("AP_P_mm")), 1.0);
    // Accuracy is what compensation fixes; the joint noise (0.002 deg) leaves AP_P near the noise level.
    EXPECT_LT(iso.Number(a, iso.Column("AP_P_mm")), 0.05);
    // Repeatability is the arm's own: the same joint noise gives nearly the same RP with or without it.
    const double rp_b = iso.Number(b, iso.Column("RP_l_mm")), rp_a = iso.Number(a, iso.Column("RP_l_mm"));
    EXPECT_GT(rp_a, 0.0);
    EXPECT_NEAR(rp_a / rp_b, 1.0, 0.2);
  }
}

TEST_F(StudyRunTest, AnEstimatorThatThrowsGivesAStatusNotACrash) {
  TempDir tmp;
  Run(tmp.path("r"), 2);
  const auto rows = Rows(tmp.path("r"), "sweep", "throws", "jacobian_ik", "targets");
  ASSERT_EQ(rows.size(), 2u);
  for (auto row : rows) {
    EXPECT_EQ(row["status"], "failed");
    EXPECT_EQ(row["estimation_status"], "error");
    EXPECT_NE(row["note"].find("never gets"), std::string::npos);
    EXPECT_EQ(row["position_error_mean_mm"], "");
  }
  const std::string report = ReadText(tmp.path("r") + "/report.md");
  EXPECT_NE(report.find("2 failed"), std::string::npos);
}

TEST_F(StudyRunTest, ReportLinksPlotsThatArePaperFigures) {
  TempDir tmp;
  Run(tmp.path("r"), 2);
  const std::string report = ReadText(tmp.path("r") + "/report.md");
  for (const char* part : {"# Study: small", "## What was run", "## Dataset random", "### Validation targets",
                           "### ISO 9283: cube", "### Parameters", "### Compensator convergence", "## Times",
                           "**before**", "oracle / jacobian_ik", "AP_P (mm)"}) {
    EXPECT_NE(report.find(part), std::string::npos) << part;
  }
  const std::regex link(R"(\!\[[^\]]*\]\((plots/[A-Za-z0-9_\-]+\.svg)\))");
  std::set<std::string> kinds;
  int links = 0;
  for (auto it = std::sregex_iterator(report.begin(), report.end(), link); it != std::sregex_iterator(); ++it) {
    ++links;
    const std::string path = (*it)[1];
    SCOPED_TRACE(path);
    kinds.insert(path.substr(6, path.find('_') - 6));
    const std::string svg = ReadText(tmp.path("r") + "/" + path);
    ASSERT_FALSE(svg.empty());
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
    // Balanced tags: every element opened is closed (or self-closing).
    const std::regex open(R"(<([a-zA-Z]+)[ >])"), self(R"(/>)"), close(R"(</[a-zA-Z]+>)");
    const auto count = [&](const std::regex& r) {
      return std::distance(std::sregex_iterator(svg.begin(), svg.end(), r), std::sregex_iterator());
    };
    EXPECT_EQ(count(open), count(self) + count(close));
    EXPECT_TRUE(svg.find("(mm)") != std::string::npos || svg.find("(deg)") != std::string::npos);  // units
  }
  EXPECT_GE(links, 6);
  EXPECT_EQ(kinds, (std::set<std::string>{"errors", "parameters", "convergence"}));
  EXPECT_NE(ReadText(tmp.path("r") + "/plots/convergence_random.svg").find("iteration"), std::string::npos);
  EXPECT_NE(ReadText(tmp.path("r") + "/plots/errors_random_targets.svg").find("position error (mm)"),
            std::string::npos);
}

TEST_F(StudyRunTest, SensitivitySweepGivesCurves) {
  const Study s =
      ParseStudy("name: sens\ntrials: 2\n" + testing::SeedRobotsYaml() +
                     "datasets:\n"
                     "  - {name: n, simulate: {protocol: random, poses: 12}, vary: {noise: [1um, 30um, 1mm]}}\n"
                     "estimators: [base_kabsch]\ncompensators: [jacobian_ik]\n"
                     "validation: [{name: t, random_targets: 5}]\n",
                 "sens.yaml", registries_.view());
  TempDir tmp;
  RunStudy(s, tmp.path("r"), StudyRunOptions(), registries_.view());
  const ResultTable t = ReadResultTable(tmp.path("r") + "/results.csv");
  std::set<std::string> values;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    EXPECT_EQ(t.Text(r, t.Column("knob")), "noise_um");
    values.insert(t.Text(r, t.Column("knob_value")));
  }
  EXPECT_EQ(values, (std::set<std::string>{"1", "30", "1000"}));
  const std::string report = ReadText(tmp.path("r") + "/report.md");
  EXPECT_NE(report.find("## Sensitivity: n"), std::string::npos);
  const std::string svg = ReadText(tmp.path("r") + "/plots/sensitivity_n_t.svg");
  EXPECT_NE(svg.find("position noise σ per axis (µm)"), std::string::npos);
  EXPECT_NE(svg.find("base_kabsch / jacobian_ik"), std::string::npos);
}

TEST_F(StudyRunTest, MeasuredDataIsScoredOnItsTestRows) {
  TempDir tmp;
  WriteDataset(testing::SeedMeasurements(40, 20e-6), tmp.path("measured.csv"));
  const Study s = ParseStudy(
      "name: real\ntrials: 3\nrobots: {nominal: " + testing::SourcePath("examples/robots/seed_nominal.yaml") +
          "}\ndatasets:\n"
          "  - {name: every, file: measured.csv, split: {every: 4}}\n"
          "  - {name: fraction, file: measured.csv, split: {test_fraction: 0.25}}\n"
          "estimators: [base_kabsch]\n",
      tmp.path("real.yaml"), registries_.view());
  RunStudy(s, tmp.path("r"), StudyRunOptions(), registries_.view());
  auto nominal = Rows(tmp.path("r"), "every", "none", "-", "heldout");
  auto fitted = Rows(tmp.path("r"), "every", "base_kabsch", "-", "heldout");
  ASSERT_EQ(nominal.size(), 3u);
  ASSERT_EQ(fitted.size(), 3u);
  EXPECT_EQ(nominal[0]["targets"], "10");
  // Fixed split: the same rows each trial. Random fraction: new rows each trial.
  EXPECT_EQ(fitted[0]["position_error_mean_mm"], fitted[1]["position_error_mean_mm"]);
  auto fraction = Rows(tmp.path("r"), "fraction", "base_kabsch", "-", "heldout");
  ASSERT_EQ(fraction.size(), 3u);
  EXPECT_NE(fraction[0]["position_error_mean_mm"], fraction[1]["position_error_mean_mm"]);
  const std::string report = ReadText(tmp.path("r") + "/report.md");
  EXPECT_NE(report.find("### Validation heldout"), std::string::npos);
  EXPECT_NE(report.find("Identified minus nominal value"), std::string::npos);
}

}  // namespace
}  // namespace kincal
