// The study file parser: a valid study's contents, the examples, and malformed files (errors name the key).
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "studies/study.h"
#include "tests/studies/study_test_util.h"
#include "tests/studies/test_methods.h"

namespace kincal {
namespace {

using testing::MakeTestRegistries;
using testing::SeedRobotsYaml;
using testing::SeedTruth;

class StudyFileTest : public ::testing::Test {
 protected:
  StudyFileTest() : registries_(MakeTestRegistries(SeedTruth())) {}
  Study Parse(const std::string& text) { return ParseStudy(text, "study.yaml", registries_.view()); }
  // The message of the error parsing `text` throws; fails the test when it parses.
  std::string Error(const std::string& text) {
    try {
      Parse(text);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    ADD_FAILURE() << "parsed without error:\n" << text;
    return "";
  }
  testing::TestRegistries registries_;
};

TEST_F(StudyFileTest, ReadsEverySection) {
  const Study s = Parse(testing::SmallStudyYaml());
  EXPECT_EQ(s.name, "small");
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.trials, 2);
  ASSERT_TRUE(s.truth.has_value());
  EXPECT_EQ(s.truth->robot.name, "seed_identified");
  ASSERT_EQ(s.datasets.size(), 2u);
  EXPECT_EQ(s.datasets[0].simulator.protocol, "sweep");
  EXPECT_EQ(s.datasets[0].simulator.stops, 4);
  EXPECT_DOUBLE_EQ(s.datasets[0].simulator.step, 3.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(s.datasets[0].simulator.noise_sigma, 10e-6);
  EXPECT_EQ(s.datasets[1].simulator.poses, 24);
  // The baselines come first even when the file does not name them.
  ASSERT_EQ(s.pipelines.size(), 4u);
  EXPECT_EQ(s.pipelines[0].name, "none");
  EXPECT_EQ(s.pipelines[2].name, "oracle");
  EXPECT_TRUE(s.pipelines[2].RunsOn("random"));
  EXPECT_FALSE(s.pipelines[2].RunsOn("sweep"));
  ASSERT_EQ(s.compensators.size(), 2u);
  EXPECT_EQ(s.compensators[0].name, "none");
  EXPECT_EQ(s.compensators[1].method, "jacobian_ik");
  ASSERT_EQ(s.validation.size(), 2u);
  EXPECT_EQ(s.validation[0].count, 12);
  EXPECT_EQ(s.validation[1].kind, ValidationSpec::Kind::kIso9283);
  EXPECT_DOUBLE_EQ(s.validation[1].iso.side, 0.15);
  EXPECT_EQ(s.validation[1].iso.cycles, 6);
}

TEST_F(StudyFileTest, PipelinesSplitOnCommasAndKeyOptionsByMethod) {
  const Study s = Parse("name: p\n" + SeedRobotsYaml() +
                        "datasets: [{name: d, simulate: {protocol: random, poses: 5}}]\n"
                        "estimators:\n"
                        "  - {method: \"base_kabsch, oracle\", options: {base_kabsch: {}, oracle: {}}}\n"
                        "  - {name: solo, method: base_kabsch, options: {}}\n"
                        "validation: [{name: v, random_targets: 3}]\n");
  ASSERT_EQ(s.pipelines.size(), 3u);
  EXPECT_EQ(s.pipelines[1].name, "base_kabsch+oracle");
  EXPECT_EQ(s.pipelines[1].methods, (std::vector<std::string>{"base_kabsch", "oracle"}));
  EXPECT_EQ(s.pipelines[2].name, "solo");
}

TEST_F(StudyFileTest, VariantsAndWorkItemsFollowTheStudyOrder) {
  const Study s = Parse("name: v\ntrials: 2\n" + SeedRobotsYaml() +
                        "datasets:\n"
                        "  - {name: a, simulate: {protocol: random, poses: 5}, vary: {noise: [1um, 0.01mm, 100um]}}\n"
                        "  - {name: b, simulate: {protocol: sweep, stops: 3}, vary: {arc: [10, 40]}}\n"
                        "estimators: [{method: base_kabsch, datasets: [b]}]\n"
                        "validation: [{name: v, random_targets: 3}]\n");
  const std::vector<DatasetVariant> variants = Variants(s);
  ASSERT_EQ(variants.size(), 5u);
  EXPECT_EQ(variants[1].label, "a[noise=0.01mm]");
  EXPECT_EQ(variants[1].knob, "noise_um");
  EXPECT_NEAR(variants[1].knob_value, 10.0, 1e-12);
  EXPECT_DOUBLE_EQ(variants[1].simulator.noise_sigma, 1e-5);
  EXPECT_EQ(variants[4].knob, "arc_deg");
  EXPECT_NEAR(variants[4].simulator.step, 20.0 * M_PI / 180.0, 1e-15);  // 40 deg over 3 stops
  const std::vector<WorkItem> items = WorkItems(s, variants);
  // a: 3 variants x 2 trials x none; b: 2 variants x 2 trials x (none, base_kabsch).
  ASSERT_EQ(items.size(), 3u * 2 + 2u * 2 * 2);
  for (size_t i = 0; i < items.size(); ++i) EXPECT_EQ(items[i].index, static_cast<int>(i));
  EXPECT_EQ(items[6].variant, 3);
  EXPECT_EQ(items[6].pipeline, 0);
  EXPECT_EQ(items[7].pipeline, 1);
  // Seeds depend on dataset, variant and trial only.
  EXPECT_NE(DatasetSeed(s, variants[0], 0), DatasetSeed(s, variants[0], 1));
  EXPECT_NE(DatasetSeed(s, variants[0], 0), DatasetSeed(s, variants[1], 0));
  EXPECT_EQ(DatasetSeed(s, variants[3], 1), DatasetSeed(s, variants[3], 1));
}

struct Malformed {
  std::string name;
  std::string body;                   // after the robots block
  std::vector<std::string> expected;  // substrings of the message
};

TEST_F(StudyFileTest, MalformedFilesNameTheKeyAndPlace) {
  const std::string datasets = "datasets: [{name: d, simulate: {protocol: random, poses: 5}}]\n";
  const std::string validation = "validation: [{name: v, random_targets: 3}]\n";
  const std::vector<Malformed> cases = {
      {"unknown top-level key", datasets + validation + "trails: 3\n", {"study.yaml:", "trails", "unknown key"}},
      {"bad noise",
       "datasets:\n  - name: d\n    simulate: {protocol: random, noise: ten}\n" + validation,
       {"datasets[0].simulate.noise", "ten"}},
      {"unknown simulator key",
       "datasets:\n  - {name: d, simulate: {protocol: random, posses: 5}}\n" + validation,
       {"datasets[0].simulate.posses", "unknown key"}},
      {"unknown protocol",
       "datasets:\n  - {name: d, simulate: {protocol: spiral}}\n" + validation,
       {"datasets[0].simulate.protocol", "spiral"}},
      {"unknown method",
       datasets + validation + "estimators: [least_squarez]\n",
       {"estimators[0]: unknown method 'least_squarez'"}},
      {"unknown method option",
       datasets + validation + "estimators:\n  - {method: base_kabsch, options: {bogus: 1}}\n",
       {"estimators[0].options", "bogus"}},
      {"unknown compensator",
       datasets + validation + "compensators: [{method: nope}]\n",
       {"compensators[0].method", "unknown method 'nope'"}},
      {"trials zero", datasets + validation + "trials: 0\n", {"study.yaml:7:9: trials: must be >= 1, got '0'"}},
      {"duplicate dataset",
       "datasets:\n  - {name: d, simulate: {}}\n  - {name: d, simulate: {}}\n" + validation,
       {"datasets[1].name", "duplicate"}},
      {"unknown knob",
       "datasets:\n  - {name: d, simulate: {}, vary: {speed: [1, 2]}}\n" + validation,
       {"datasets[0].vary.speed", "unknown knob"}},
      {"knob needs sweeps",
       "datasets:\n  - {name: d, simulate: {protocol: random}, vary: {arc: [10]}}\n" + validation,
       {"datasets[0].vary.arc", "sweep protocol"}},
      {"estimator on unknown dataset",
       datasets + validation + "estimators: [{method: oracle, datasets: [x]}]\n",
       {"estimators[0].datasets[0]", "unknown dataset 'x'"}},
      {"negative cube side",
       datasets + "validation: [{name: c, iso9283: {side: -1mm}}]\n",
       {"validation[0].iso9283.side"}},
      {"no validation", datasets, {"validation", "missing key"}},
      {"bad joint limits",
       datasets + "validation: [{name: v, random_targets: 3, joint_limits: [[0, 1]]}]\n",
       {"validation[0].joint_limits", "expected 6"}},
      {"split on simulated data",
       "datasets: [{name: d, simulate: {}, split: {every: 2}}]\n" + validation,
       {"datasets[0].split"}},
      {"missing data file", "datasets: [{name: d, file: no_such_file.csv}]\n", {"datasets[0].file", "cannot read"}},
      {"invalid yaml", "datasets: [{name: d\n", {"study.yaml:", "invalid YAML"}},
  };
  for (const Malformed& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string message = Error("name: bad\n" + SeedRobotsYaml() + c.body);
    for (const auto& part : c.expected) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

TEST_F(StudyFileTest, ErrorsGiveTheLineAndColumnOfTheKey) {
  const std::string text = "name: bad\n" + SeedRobotsYaml() +  // lines 1-4
                           "datasets:\n"                       // 5
                           "  - name: d\n"                     // 6
                           "    simulate:\n"                   // 7
                           "      protocol: random\n"          // 8
                           "      poses: many\n"               // 9
                           "validation: [{name: v, random_targets: 3}]\n";
  EXPECT_NE(Error(text).find("study.yaml:9:14: datasets[0].simulate.poses"), std::string::npos) << Error(text);
}

TEST_F(StudyFileTest, MissingTruthIsAnErrorForSimulatedData) {
  const std::string message =
      Error("name: t\nrobots: {nominal: " + testing::SourcePath("examples/robots/seed_nominal.yaml") +
            "}\ndatasets: [{name: d, simulate: {}}]\nvalidation: [{name: v, random_targets: 2}]\n");
  EXPECT_NE(message.find("robots.truth"), std::string::npos) << message;
}

// Every example study parses, unless it names a method this build does not register (the estimators and
// compensators arrive in other modules), reads ../shared/data where that folder is absent (and
// KINCAL_REQUIRE_DATA is not 1), or reads a dataset not yet converted into the build folder; then it is
// skipped, with the message.
TEST(ExampleStudies, Parse) {
  const std::string dir = testing::SourcePath("examples/studies");
  int parsed = 0, files = 0;
  std::vector<std::string> skipped;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    try {
      const Study s = ReadStudyFile(entry.path().string());
      EXPECT_FALSE(s.datasets.empty());
      EXPECT_FALSE(Variants(s).empty());
      ++parsed;
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      // A study of measured data (../shared/data) stops before any work without it, naming the file.
      // Under KINCAL_REQUIRE_DATA=1 that is a failure too.
      const bool no_shared_data = !testing::SharedDataRequired() &&
                                  !std::filesystem::exists(entry.path().parent_path() / "../../../shared/data") &&
                                  message.find("cannot read") != std::string::npos &&
                                  message.find("shared/data/") != std::string::npos;
      // A study of data converted into the build folder first (scripts/ur10_ipa2021_dataset; its header
      // says how) is skipped until that is done: the real-data tests convert and run it.
      const bool not_converted =
          message.find("cannot read") != std::string::npos && message.find("/build/") != std::string::npos;
      if (message.find("unknown method") == std::string::npos && !no_shared_data && !not_converted) {
        ADD_FAILURE() << message;
      } else {
        skipped.push_back(entry.path().filename().string() + ": " + message);
      }
    }
  }
  EXPECT_GE(files, 3);
  for (const auto& s : skipped) std::printf("not checked here: %s\n", s.c_str());
  if (!skipped.empty() && parsed == 0) {
    std::string all;
    for (const auto& s : skipped) all += s + "\n";
    GTEST_SKIP() << "methods not registered in this build:\n" << all;
  }
}

}  // namespace
}  // namespace kincal
