// The study file's option sections, declared once (studies/study_options.h): bad values fail with the key's
// path, line and column (through the parser and through `kincal study`, exit 2), IsValid checks the same
// requirements, and the documented defaults read back as the defaults.
#include <gtest/gtest.h>

#include "studies/study.h"
#include "studies/study_options.h"
#include "tests/studies/study_test_util.h"
#include "tests/studies/test_methods.h"

namespace kincal {
namespace {

using testing::SeedRobotsYaml;

std::string ParseError(const std::string& text) {
  try {
    ParseStudy(text, "study.yaml", testing::MakeTestRegistries(testing::SeedTruth()).view());
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "parsed without error:\n" << text;
  return "";
}

// Lines 1-4: name and robots; `datasets` and `validation` follow from line 5.
std::string Study(const std::string& simulate, const std::string& iso = "{side: 150mm}") {
  return "name: bad\n" + SeedRobotsYaml() +  // 1-4
         "datasets:\n"                       // 5
         "  - name: d\n"                     // 6
         "    simulate:\n"                   // 7
         "      protocol: random\n"          // 8
         "      " +
         simulate + "\n" +                     // 9
         "validation:\n"                       // 10
         "  - {name: v, random_targets: 3}\n"  // 11
         "  - name: cube\n"                    // 12
         "    iso9283: " +
         iso + "\n";  // 13
}

TEST(StudyOptions, OutOfRangeValuesNameTheKeyLineAndColumn) {
  EXPECT_EQ(ParseError(Study("noise: -5um")),
            "study.yaml:9:14: datasets[0].simulate.noise: must be finite and >= 0, got '-5um'");
  EXPECT_EQ(ParseError(Study("poses: 0")), "study.yaml:9:14: datasets[0].simulate.poses: must be >= 1, got '0'");
  EXPECT_EQ(ParseError(Study("protocol_: random")).find("study.yaml:9:7: datasets[0].simulate.protocol_: unknown key"),
            0u);
  EXPECT_EQ(ParseError("seed: -3\n" + Study("poses: 5")), "study.yaml:1:7: seed: expected an integer >= 0");
  EXPECT_EQ(ParseError("threads: -1\n" + Study("poses: 5")), "study.yaml:1:10: threads: must be >= 0, got '-1'");
  EXPECT_EQ(ParseError(Study("poses: 5") + "  - {name: w, random_targets: 0}\n"),
            "study.yaml:14:31: validation[2].random_targets: must be >= 1, got '0'");
  EXPECT_EQ(ParseError(Study("poses: 5") + "  - {name: w, random_targets: 5, orientation: yes please}\n"),
            "study.yaml:14:47: validation[2].orientation: expected true or false");
  EXPECT_EQ(ParseError(Study("poses: 5", "{side: 150mm, cycles: 1}")),
            "study.yaml:13:36: validation[1].iso9283.cycles: must be >= 2, got '1'");
  EXPECT_EQ(ParseError(Study("poses: 5", "{joint_noise: -0.1}")),
            "study.yaml:13:28: validation[1].iso9283.joint_noise: must be finite and >= 0, got '-0.1'");
}

TEST(StudyOptions, WrongTypesNameTheKeyLineAndColumn) {
  EXPECT_EQ(ParseError(Study("stops: many")), "study.yaml:9:14: datasets[0].simulate.stops: expected a number");
  EXPECT_EQ(ParseError(Study("orientation: maybe")),
            "study.yaml:9:20: datasets[0].simulate.orientation: expected true or false");
  EXPECT_EQ(ParseError(Study("marker: [1, 2]")),
            "study.yaml:9:15: datasets[0].simulate.marker: expected [x, y, z] in mm, got '[1, 2]'");
  EXPECT_EQ(ParseError(Study("poses: 5", "{side: wide}")).find("study.yaml:13:21: validation[1].iso9283.side: "), 0u);
  // What the table cannot know is checked after it, at the same place: the robot has 6 joints.
  EXPECT_EQ(ParseError(Study("start: [0, 0, 0]")),
            "study.yaml:9:14: datasets[0].simulate.start: expected 6 angles (deg), got 3");
}

TEST(StudyOptions, KincalStudyExitsWithTwoAndThePlace) {
  testing::TempDir tmp;
  testing::WriteText(tmp.path("bad.yaml"), Study("noise: -5um"));
  const auto r = testing::RunKincal("study " + tmp.path("bad.yaml") + " --out " + tmp.path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:9:14: datasets[0].simulate.noise: must be finite and >= 0"), std::string::npos)
      << r.err;
  testing::WriteText(tmp.path("bad.yaml"), Study("poses: 5", "{cycles: thirty}"));
  const auto t = testing::RunKincal("study " + tmp.path("bad.yaml") + " --out " + tmp.path("out"));
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.err.find("bad.yaml:13:23: validation[1].iso9283.cycles: expected a number"), std::string::npos) << t.err;
}

TEST(StudyOptions, PlainLengthsAreMillimetresAndAnglesDegrees) {
  const testing::TestRegistries registries = testing::MakeTestRegistries(testing::SeedTruth());
  const kincal::Study s = ParseStudy(
      Study("noise: 0.01\n      noise_range: 5um\n      step: 3\n      orientation_noise: 0.5\n      marker: [40, 30, "
            "100]",
            "{side: 150, measurement_noise: 0.002mm, joint_noise: 0.01, center_configuration: [0, 30, 30, 0, 45, 0]}"),
      "study.yaml", registries.view());
  const SimulatorOptions& o = s.datasets[0].simulator;
  EXPECT_DOUBLE_EQ(o.noise_sigma, 1e-5);
  EXPECT_DOUBLE_EQ(o.noise_range_coefficient, 5e-6);
  EXPECT_DOUBLE_EQ(o.step, 3 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(o.orientation_noise, 0.5 * M_PI / 180.0);
  ASSERT_TRUE(s.datasets[0].marker.has_value());
  EXPECT_DOUBLE_EQ((*s.datasets[0].marker)[2], 0.1);
  const Iso9283Spec& iso = s.validation[1].iso;
  EXPECT_DOUBLE_EQ(iso.side, 0.15);
  EXPECT_DOUBLE_EQ(iso.measurement_noise, 2e-6);
  EXPECT_DOUBLE_EQ(iso.joint_noise, 0.01 * M_PI / 180.0);
  ASSERT_EQ(iso.center_configuration.size(), 6);
  EXPECT_DOUBLE_EQ(iso.center_configuration[4], 45 * M_PI / 180.0);
}

TEST(StudyOptions, IsValidChecksWhatTheFileReaderChecks) {
  SimulatorOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.stops = 1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "stops must be >= 2, got 1");
  o = SimulatorOptions();
  o.noise_sigma = -1e-6;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "noise must be finite and >= 0, got -0.001 mm");
  Iso9283Spec iso;
  EXPECT_TRUE(iso.IsValid(&why)) << why;
  iso.side = 0.0;
  EXPECT_FALSE(iso.IsValid(&why));
  EXPECT_EQ(why, "side must be positive, got 0 mm");
  MeasuredIso9283Spec measured;
  EXPECT_TRUE(measured.IsValid(&why)) << why;
  measured.min_cycles = 1;
  EXPECT_FALSE(measured.IsValid(&why));
}

// Every documented key, written with its documented default, reads back as the default: the docs show
// what the parser reads, in the file's units.
TEST(StudyOptions, DocumentedDefaultsReadBackAsTheDefaults) {
  const auto docs = StudyOptionDocs();
  ASSERT_EQ(docs.size(), 5u);
  const auto map_of = [](const std::vector<OptionDoc>& section) {
    std::string map;
    for (const OptionDoc& d : section) {
      std::string value = d.default_value;
      if (value.size() > 3 && value.compare(value.size() - 3, 3, " mm") == 0)
        value = value.substr(0, value.size() - 3) + "mm";
      map += (map.empty() ? "" : ", ") + d.key + ": " + value;
    }
    return "{" + map + "}";
  };
  EXPECT_EQ(docs[1].first, "datasets[].simulate");
  EXPECT_EQ(docs[4].first, "validation[].iso9283");
  // A validation set's random_targets has no default (a set gives it or a cube); its orientation has.
  ASSERT_EQ(docs[3].second.size(), 2u);
  EXPECT_EQ(docs[3].second[0].key, "random_targets");
  EXPECT_EQ(docs[3].second[1].default_value, "true");
  std::string top;  // the top level's settings, one line each
  for (const OptionDoc& d : docs[0].second) top += d.key + ": " + d.default_value + "\n";
  const testing::TestRegistries registries = testing::MakeTestRegistries(testing::SeedTruth());
  const kincal::Study s = ParseStudy("name: docs\n" + top + SeedRobotsYaml() +
                                         "datasets:\n  - {name: d, simulate: " + map_of(docs[1].second) +
                                         // (a measured dataset's file is only checked readable when parsing)
                                         "}\n  - {name: m, file: " + testing::SourcePath("examples/studies/README.md") +
                                         ", split: {every: 2}, iso9283: " + map_of(docs[2].second) + "}\n" +
                                         "validation:\n  - {name: cube, iso9283: " + map_of(docs[4].second) + "}\n",
                                     "study.yaml", registries.view());
  const StudySettings settings;
  EXPECT_EQ(s.seed, settings.seed);
  EXPECT_EQ(s.trials, settings.trials);
  EXPECT_EQ(s.threads, settings.threads);
  const SimulatorOptions& o = s.datasets[0].simulator;
  const SimulatorOptions defaults;
  EXPECT_EQ(o.protocol, defaults.protocol);
  EXPECT_EQ(o.poses, defaults.poses);
  EXPECT_EQ(o.stops, defaults.stops);
  EXPECT_DOUBLE_EQ(o.step, defaults.step);
  EXPECT_EQ(o.start.size(), 0);
  EXPECT_TRUE(o.sweep_order.empty());
  EXPECT_EQ(o.noise_sigma, defaults.noise_sigma);
  EXPECT_EQ(o.orientation, defaults.orientation);
  EXPECT_FALSE(s.datasets[0].marker.has_value());
  const MeasuredIso9283Spec measured;
  EXPECT_DOUBLE_EQ(s.datasets[1].iso.tolerance, measured.tolerance);
  EXPECT_DOUBLE_EQ(s.datasets[1].iso.angle_tolerance, measured.angle_tolerance);
  EXPECT_EQ(s.datasets[1].iso.min_cycles, measured.min_cycles);
  const Iso9283Spec iso;
  EXPECT_DOUBLE_EQ(s.validation[0].iso.side, iso.side);
  EXPECT_EQ(s.validation[0].iso.cycles, iso.cycles);
  EXPECT_DOUBLE_EQ(s.validation[0].iso.joint_noise, iso.joint_noise);
}

}  // namespace
}  // namespace kincal
