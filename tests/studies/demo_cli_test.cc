// The demo and the study, merge and demo subcommands end to end.
#include <gtest/gtest.h>

#include "robot/robot_file.h"
#include "studies/demo.h"
#include "studies/results_files.h"
#include "tests/studies/study_test_util.h"
#include "tests/studies/test_methods.h"

namespace kincal {
namespace {

using testing::ReadText;
using testing::RunKincal;
using testing::TempDir;
using testing::WriteText;

TEST(Demo, EmbedsTheExampleSeedRobots) {
  EXPECT_EQ(RobotToYaml(ParseRobotYaml(SeedNominalRobotYaml(), "embedded")), RobotToYaml(testing::SeedNominal()));
  EXPECT_EQ(RobotToYaml(ParseRobotYaml(SeedIdentifiedRobotYaml(), "embedded")), RobotToYaml(testing::SeedTruth()));
}

TEST(Demo, RunsEveryRegisteredMethodOnTheDataItNeeds) {
  const testing::TestRegistries registries = testing::MakeTestRegistries(testing::SeedTruth());
  DemoOptions o;
  const Study s = ParseStudy(DemoStudyYaml(o, registries.view()), "demo.yaml", registries.view());
  ASSERT_EQ(s.datasets.size(), 2u);
  EXPECT_EQ(s.datasets[0].simulator.protocol, "sweep");
  EXPECT_EQ(s.datasets[0].simulator.stops, 20);
  EXPECT_NEAR(s.datasets[0].simulator.step, 2.0 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(s.datasets[1].simulator.poses, 120);  // the same size as the sweep
  std::vector<std::string> names;
  for (const auto& p : s.pipelines) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"none", "base_kabsch", "oracle", "throws"}));
  EXPECT_EQ(s.pipelines[1].datasets, std::vector<std::string>{"random"});
  ASSERT_EQ(s.compensators.size(), 2u);
  EXPECT_EQ(s.compensators[1].name, "jacobian_ik");
  ASSERT_EQ(s.validation.size(), 3u);
  EXPECT_EQ(s.validation[0].count, 10);
  EXPECT_EQ(s.validation[1].count, 1000);
  EXPECT_EQ(s.trials, 3);
}

TEST(DemoCommand, RunsQuicklyAndQuotesTheSeed) {
  TempDir tmp;
  const auto r =
      RunKincal("demo --out " + tmp.path("demo") + " --trials 1 --targets 20 --stops 5 --no-iso --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2.83 mm -> 0.54 mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("before"), std::string::npos);
  EXPECT_NE(r.out.find("demo finished in"), std::string::npos);
  EXPECT_NE(ReadText(tmp.path("demo") + "/report.md").find("## What was run"), std::string::npos);
  // The demo leaves its study file, which reruns as a study.
  const auto again = RunKincal("study " + tmp.path("demo") + "/study.yaml --out " + tmp.path("again"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(ReadText(tmp.path("again") + "/results.csv"), ReadText(tmp.path("demo") + "/results.csv"));
}

TEST(StudyCommand, MalformedStudyIsExitStatusTwoNamingTheKey) {
  TempDir tmp;
  WriteText(tmp.path("bad.yaml"), "name: bad\n" + testing::SeedRobotsYaml() +
                                      "datasets: [{name: d, simulate: {protocol: random, noise: loud}}]\n"
                                      "validation: [{name: v, random_targets: 2}]\n");
  const auto r = RunKincal("study " + tmp.path("bad.yaml") + " --out " + tmp.path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("datasets[0].simulate.noise"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.yaml:5:"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);  // one line
  const auto shard = RunKincal("study " + tmp.path("bad.yaml") + " --out " + tmp.path("out") + " --shard 3/2");
  EXPECT_EQ(shard.exit_code, 2);
  const auto merge = RunKincal("merge " + tmp.path("nothing") + " --out " + tmp.path("m"));
  EXPECT_EQ(merge.exit_code, 2);
}

TEST(StudyCommand, ShardsThenMergeEqualsOneRun) {
  TempDir tmp;
  WriteText(tmp.path("s.yaml"), "name: cli\ntrials: 3\n" + testing::SeedRobotsYaml() +
                                    "datasets: [{name: d, simulate: {protocol: random, poses: 10}}]\n"
                                    "validation: [{name: v, random_targets: 4}]\n");
  ASSERT_EQ(RunKincal("study " + tmp.path("s.yaml") + " --out " + tmp.path("whole")).exit_code, 0);
  const auto a = RunKincal("study " + tmp.path("s.yaml") + " --out " + tmp.path("a") + " --shard 1/2");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.out.find("kincal merge"), std::string::npos);
  ASSERT_EQ(RunKincal("study " + tmp.path("s.yaml") + " --out " + tmp.path("b") + " --shard 2/2").exit_code, 0);
  // Progress goes to stderr as plain lines when it is not a terminal.
  const auto m = RunKincal("merge " + tmp.path("a") + " " + tmp.path("b") + " --out " + tmp.path("m"));
  ASSERT_EQ(m.exit_code, 0) << m.err;
  for (const char* f : {"results.csv", "parameters.csv", "study.json"}) {
    EXPECT_EQ(ReadText(tmp.path("m") + "/" + f), ReadText(tmp.path("whole") + "/" + f)) << f;
  }
  EXPECT_NE(ReadText(tmp.path("m") + "/report.md").find("# Study: cli"), std::string::npos);
}

}  // namespace
}  // namespace kincal
