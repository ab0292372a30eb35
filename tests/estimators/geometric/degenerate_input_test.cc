// Degenerate input is a clear std::invalid_argument from the estimators and exit status 2 from
// `kincal identify`.
#include <gtest/gtest.h>

#include "estimators/geometric/geometric_estimator.h"
#include "estimators/ratio_regression/ratio_regression_estimator.h"
#include "tests/estimators/geometric/seed_fixture.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

struct Case {
  std::string name;
  Dataset data;
  std::string expected;  // part of the message
};

std::vector<Case> DegenerateCases() {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  const Dataset good = SeedSweeps(nominal, truth, 0.0, 1);
  std::vector<Case> cases;
  cases.push_back({"two stops", SeedSweeps(nominal, truth, 0.0, 1, 2), "at least 3 stops"});
  Dataset collinear = good;
  int k = 0;
  for (auto& m : collinear.rows) {
    if (m.sweep == 4) m.p = Eigen::Vector3d(0.5, 0.1, 0.2) + 0.01 * (k++) * Eigen::Vector3d(1, 2, -1);
  }
  cases.push_back({"collinear stops", collinear, "straight line"});
  Dataset coincident = good;
  for (auto& m : coincident.rows) {
    if (m.sweep == 2) m.p = Eigen::Vector3d(0.5, 0.1, 0.2);
  }
  cases.push_back({"coincident stops", coincident, "barely moves"});
  Robot nominal_on_axis = nominal, truth_on_axis = truth;  // the marker on axis 6
  nominal_on_axis.model().SetTool(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1)));
  truth_on_axis.model().SetTool(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1)));
  cases.push_back({"marker on the axis", SeedSweeps(nominal_on_axis, truth_on_axis, 0.0, 1), "on the joint's axis"});
  Dataset out_of_range = good;
  out_of_range.rows[5].sweep = 7;
  cases.push_back({"sweep index out of range", out_of_range, "out of range"});
  Dataset never = good;
  std::vector<Measurement> kept;
  for (const auto& m : never.rows) {
    if (m.sweep != 3) kept.push_back(m);
  }
  never.rows = kept;
  cases.push_back({"joint never swept", never, "joint 3 was never swept"});
  Dataset moving = good;
  moving.rows[30].q[0] += 0.01;  // joint 1 moves during the sweep of joint 5
  cases.push_back({"another joint moves", moving, "joint 1 moves during the sweep of joint 5"});
  Dataset free_only = good;
  for (auto& m : free_only.rows) m.sweep = 0;
  cases.push_back({"no sweep column", free_only, "no sweep rows"});
  return cases;
}

TEST(DegenerateInput, EstimatorsThrowClearErrors) {
  const Robot nominal = SeedNominal();
  for (const Case& c : DegenerateCases()) {
    SCOPED_TRACE(c.name);
    Robot identified;
    try {
      GeometricEstimator().Estimate(nominal, c.data, &identified);
      ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
  // The ratio regression refuses the same arcs, and a robot without drives.
  Robot identified;
  EXPECT_THROW(RatioRegressionEstimator().Estimate(nominal, DegenerateCases()[1].data, &identified),
               std::invalid_argument);
  Robot no_drives = nominal;
  no_drives.drives.reset();
  EXPECT_THROW(RatioRegressionEstimator().Estimate(no_drives, SeedSweeps(no_drives, no_drives, 0.0, 1), &identified),
               std::invalid_argument);
  // Prismatic joints cannot be swept in circles.
  const Robot prismatic = ParseRobotYaml(R"(
name: p
convention: mdh
units: {length: m, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 0}
  - {alpha: 90, a: 0.1, theta: 0, d: 0, type: prismatic}
tool: {xyz: [0.1, 0.05, 0.02]}
)",
                                         "prismatic");
  EXPECT_THROW(GeometricEstimator().Estimate(prismatic, SeedSweeps(prismatic, prismatic, 0.0, 1), &identified),
               std::invalid_argument);
}

TEST(DegenerateInput, CommandLineExitsWithStatusTwo) {
  TempDir dir;
  const std::string nominal = SourcePath("examples/robots/seed_nominal.yaml");
  for (const Case& c : DegenerateCases()) {
    SCOPED_TRACE(c.name);
    if (c.name == "marker on the axis") continue;  // needs its own robot file; covered above
    const std::string data = dir.path("data.csv");
    WriteDataset(c.data, data);
    for (const std::string method : {"geometric", "geometric,ratio_regression"}) {
      const CommandResult r = RunKincal("identify --nominal " + nominal + " --data " + data + " --method " + method +
                                        " --out " + dir.path("out.yaml"));
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
  }
  // A good dataset goes through, writing the robot and a report of both stages.
  const Robot n = SeedNominal();
  WriteDataset(SeedSweeps(n, SeedTruth(), 10e-6, 1), dir.path("good.csv"));
  const CommandResult r = RunKincal("identify --nominal " + nominal + " --data " + dir.path("good.csv") +
                                    " --method geometric,ratio_regression --out " + dir.path("id.yaml") + " --report " +
                                    dir.path("report.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(ReadText(dir.path("report.json")));
  ASSERT_EQ(report["stages"].size(), 2u);
  EXPECT_EQ(report["stages"][0]["details"]["axes"].size(), 6u);
  EXPECT_EQ(report["stages"][1]["parameters"].size(), 6u);
  EXPECT_NO_THROW(ReadRobotFile(dir.path("id.yaml")));
}

}  // namespace
}  // namespace kincal::testing
