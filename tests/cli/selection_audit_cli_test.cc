// identify --select --audit (estimators/selection/selection_audit.h): every nested candidate's held-out
// RMS and max equal those of a separate identify of that candidate's robot file (same method and options,
// with the default priors selection fits with), the chosen one's equal identify's own validation, the table
// and the summary line are printed, the same run gives the same figures, and held-out rows given as a split
// column give what --validate gives. Bad use (--audit without
// --select, or without held-out rows) exits 2 with one line and writes nothing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <tuple>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;
using testing::TempDir;

// The declared terms of the nominal, in file order; the candidates add them one group at a time in the
// order gravity, harmonic, backlash (model_selection.h).
const std::vector<std::string> kTerms = {
    "  - {joint: 3, type: backlash}\n",
    "  - {joint: 2, type: gravity}\n",
    "  - {joint: 1, type: harmonic, orders: [1]}\n",
};

// seed_nominal.yaml declaring the terms `kept` of kTerms (none: geometry).
std::string NominalWith(const TempDir& dir, const std::string& name, const std::vector<int>& kept) {
  std::string text = testing::ReadText(SourcePath("examples/robots/seed_nominal.yaml"));
  text += "velocity_limits: [250, 250, 250, 320, 320, 420]\n";
  if (!kept.empty()) text += "joint_errors:\n";
  for (int t : kept) text += kTerms[t];
  const std::string path = dir.path(name);
  testing::WriteText(path, text);
  return path;
}

nlohmann::json ReadJson(const std::string& path) { return nlohmann::json::parse(testing::ReadText(path)); }

bool FileExists(const std::string& path) { return std::ifstream(path).good(); }

int CountLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

class SelectionAuditCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // The truth: the seed's identified arm with a gravity error on joint 2 (and nothing else).
    std::string truth = testing::ReadText(SourcePath("examples/robots/seed_identified.yaml"));
    truth +=
        "velocity_limits: [250, 250, 250, 320, 320, 420]\njoint_errors:\n"
        "  - {joint: 2, type: gravity, coefficients: {link2_x: 0.02, link3_y: -0.01, link4_x: 0.005}}\n";
    testing::WriteText(dir_.path("truth.yaml"), truth);
    nominal_ = NominalWith(dir_, "declared.yaml", {0, 1, 2});
    for (const auto& [out, seed, poses] : {std::tuple{"train.csv", 5, 120}, std::tuple{"heldout.csv", 6, 60}}) {
      const auto r = RunKincal("simulate --nominal " + SourcePath("examples/robots/seed_nominal.yaml") + " --truth " +
                               dir_.path("truth.yaml") + " --protocol random --poses " + std::to_string(poses) +
                               " --noise 20um --seed " + std::to_string(seed) + " --out " + dir_.path(out));
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    testing::WriteText(dir_.path("o.yaml"), "max_iterations: 100\n");
    testing::WriteText(dir_.path("o_prior.yaml"), "max_iterations: 100\nprior: on\n");
  }

  // identify with least_squares on train.csv, held out heldout.csv, report into `report`.
  testing::CommandResult Identify(const std::string& nominal, const std::string& options, const std::string& extra,
                                  const std::string& report) {
    return RunKincal("identify --nominal " + nominal + " --data " + dir_.path("train.csv") +
                     " --method least_squares --options " + dir_.path(options) + " --validate " +
                     dir_.path("heldout.csv") + " --out " + dir_.path(report + ".yaml") + " --report " +
                     dir_.path(report + ".json") + extra);
  }

  // train.csv's rows (split train) then heldout.csv's (split test), in one file.
  void WriteSplitDataset(const std::string& path) const {
    std::string out;
    for (const auto& [file, split] : {std::pair{"train.csv", "train"}, std::pair{"heldout.csv", "test"}}) {
      std::istringstream in(testing::ReadText(dir_.path(file)));
      bool header = true;
      for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        if (header) {
          header = false;
          if (out.empty()) out += line + ",split\n";
          continue;
        }
        out += line + "," + split + "\n";
      }
    }
    testing::WriteText(path, out);
  }

  TempDir dir_;
  std::string nominal_;
};

TEST_F(SelectionAuditCli, EveryCandidateScoresWhatItsOwnIdentifyScores) {
  auto r = Identify(nominal_, "o.yaml", " --select --audit", "audit");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json report = ReadJson(dir_.path("audit.json"));
  const nlohmann::json& selection = report.at("stages").back().at("details").at("selection");
  const nlohmann::json& candidates = selection.at("candidates");
  ASSERT_EQ(candidates.size(), 5u);
  // Candidate c holds the first c groups in the selection's order: compliance 2 (one coefficient of the
  // gravity term), gravity 2, harmonic 1, backlash 3.
  const std::vector<std::vector<int>> kept = {{}, {1}, {1}, {1, 2}, {0, 1, 2}};
  const std::vector<std::string> names = {"geometry", "+ compliance 2", "+ gravity 2", "+ harmonic 1",
                                          "+ backlash 3"};
  EXPECT_EQ(selection.at("audit").at("held_out_rows").get<int>(), 60);
  for (size_t c = 0; c < candidates.size(); ++c) {
    SCOPED_TRACE(names[c]);
    EXPECT_EQ(candidates[c].at("candidate").get<std::string>(), names[c]);
    EXPECT_TRUE(candidates[c].at("held_out_rms_mm").is_number());
    if (c == 1) continue;  // its own identify would need the held coefficients named in `fixed`
    const std::string file = NominalWith(dir_, "candidate" + std::to_string(c) + ".yaml", kept[c]);
    // The default priors selection fits with, given: `prior: on`.
    const auto own = Identify(file, "o_prior.yaml", "", "own" + std::to_string(c));
    ASSERT_EQ(own.exit_code, 0) << own.err;
    const nlohmann::json v = ReadJson(dir_.path("own" + std::to_string(c) + ".json")).at("validation").at("identified");
    EXPECT_EQ(v.at("count").get<int>(), 60);
    EXPECT_NEAR(candidates[c].at("held_out_rms_mm").get<double>(), v.at("rms").get<double>(), 1e-9);
    EXPECT_NEAR(candidates[c].at("held_out_max_mm").get<double>(), v.at("max").get<double>(), 1e-9);
    EXPECT_NE(candidates[c].at("held_out_status").get<std::string>(), "failed");
  }
  // The truth's gravity error: geometry alone predicts held-out rows worse than the gravity candidate.
  EXPECT_GT(candidates[0].at("held_out_rms_mm").get<double>(), 1.5 * candidates[2].at("held_out_rms_mm").get<double>());

  // The chosen candidate is what identify identified: its held-out figures are the validation's.
  int chosen = -1;
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (candidates[c].at("chosen").get<bool>()) chosen = static_cast<int>(c);
  }
  ASSERT_GE(chosen, 0);
  const nlohmann::json& validation = report.at("validation").at("identified");
  EXPECT_NEAR(candidates[chosen].at("held_out_rms_mm").get<double>(), validation.at("rms").get<double>(), 1e-9);

  // The summary line: chosen, best (lowest held-out RMS), ratio, geometry; printed with the table.
  int best = 0;
  for (size_t c = 1; c < candidates.size(); ++c) {
    if (candidates[c].at("held_out_rms_mm").get<double>() < candidates[best].at("held_out_rms_mm").get<double>()) {
      best = static_cast<int>(c);
    }
  }
  const double rms_chosen = candidates[chosen].at("held_out_rms_mm").get<double>();
  const double rms_best = candidates[best].at("held_out_rms_mm").get<double>();
  char expected[300];
  std::snprintf(expected, sizeof expected,
                "chosen %s: held-out RMS %.4f mm, best candidate %s: %.4f mm (ratio %.4f), geometry %.4f mm",
                names[chosen].c_str(), rms_chosen, names[best].c_str(), rms_best, rms_chosen / rms_best,
                candidates[0].at("held_out_rms_mm").get<double>());
  EXPECT_EQ(selection.at("audit").at("summary").get<std::string>(), expected);
  EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("held-out RMS"), std::string::npos) << r.out;

  // Deterministic: the same run, the same figures.
  r = Identify(nominal_, "o.yaml", " --select --audit", "again");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadJson(dir_.path("again.json")).at("stages").back().at("details").at("selection"), selection);

  // The held-out rows as the test rows of a split column: the same training rows, the same figures for the
  // candidates without a backlash term (there the first held-out row's previous pose is the last training
  // row's, not none), and the chosen one's still identify's validation.
  WriteSplitDataset(dir_.path("split.csv"));
  r = RunKincal("identify --nominal " + nominal_ + " --data " + dir_.path("split.csv") +
                " --method least_squares --options " + dir_.path("o.yaml") + " --select --audit --out " +
                dir_.path("split.yaml") + " --report " + dir_.path("split.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json split = ReadJson(dir_.path("split.json"));
  const nlohmann::json& split_selection = split.at("stages").back().at("details").at("selection");
  EXPECT_EQ(split_selection.at("audit").at("held_out_rows").get<int>(), 60);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(split_selection.at("candidates")[c].at("held_out_rms_mm"), candidates[c].at("held_out_rms_mm")) << c;
  }
  for (const auto& c : split_selection.at("candidates")) {
    if (c.at("chosen").get<bool>()) {
      EXPECT_NEAR(c.at("held_out_rms_mm").get<double>(), split.at("validation").at("identified").at("rms").get<double>(),
                  1e-9);
    }
  }
}

TEST_F(SelectionAuditCli, BadUseExitsTwoWithOneLine) {
  auto r = Identify(nominal_, "o.yaml", " --audit", "no_select");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(CountLines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--audit needs --select"), std::string::npos) << r.err;
  EXPECT_FALSE(FileExists(dir_.path("no_select.yaml")));

  // Without --validate and without a split column: no held-out rows.
  r = RunKincal("identify --nominal " + nominal_ + " --data " + dir_.path("train.csv") +
                " --method least_squares --select --audit --out " + dir_.path("no_heldout.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(CountLines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--audit needs held-out rows"), std::string::npos) << r.err;
  EXPECT_FALSE(FileExists(dir_.path("no_heldout.yaml")));
}

}  // namespace
}  // namespace kincal
