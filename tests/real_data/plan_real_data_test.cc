// Planned against random measurement poses on real arms of ../shared/data (skips without the data, fails
// with KINCAL_REQUIRE_DATA=1). The even rows with their measurements are the candidate pool, the odd rows
// are scored. K poses planned from the pool (planning/plan.h) and fitted as kincal fits geometry
// (least_squares, positions, the default priors) should predict the odd rows at or below the median of
// 20 random draws of K from the same pool, fitted the same way. Every criterion's figure is printed, for
// K = 30 and 60 (docs/planning.md has the table).
// - The UR10 of ur10_ipa2021 series C, on which the default criterion was chosen: asserted for K = 30.
//   At K = 60 the default plan is 0.5 % above the median (0.5222 against 0.5196 mm) and no criterion is
//   reliably below it (docs/planning.md says why): that target is not met, and the figures are printed.
// - The IRB 120 of irb120_faro, reflector 1, which was not used in developing the plan (no acceptance
//   angle: the data do not say where the reflector points): asserted for K = 30 and 60.
// The tracker sits where the data put it: the origin of the measurement frame, in the base frame of a fit
// of every pool row. The plan chooses from the pool rows that meet the constraints with it, and the
// draws are taken from the same rows.
#include <algorithm>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "framework/dataset.h"
#include "framework/random.h"
#include "planning/plan.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "tests/estimators/irb120_faro.h"
#include "tests/real_data/ur10_ipa2021_util.h"

namespace kincal::testing {
namespace {

struct Arm {
  std::string name;
  Robot nominal;
  Dataset pool, test;
  double acceptance_angle = PlanOptions().acceptance_angle;  // rad
};

// Held-out RMS (mm) of geometry fitted on the pool rows `rows`.
double HeldOutRms(const Arm& arm, const std::vector<int>& rows) {
  Robot identified;
  Estimators()
      .Create("least_squares", YAML::Load("{max_iterations: 200, prior: on}"))
      ->Estimate(arm.nominal, arm.pool.SelectRows(rows), &identified);
  return EvaluatePredictions(arm.nominal, identified, arm.test).position_stats.rms * 1e3;
}

// The default options with the data's tracker: at the measurement frame's origin, in the base frame of a
// fit of every pool row.
PlanOptions TrackerOfTheData(const Arm& arm) {
  Robot identified;
  Estimators().Create("least_squares", YAML::Load("{prior: on}"))->Estimate(arm.nominal, arm.pool, &identified);
  const Eigen::Vector3d tracker = identified.SessionBase(arm.pool.rows[0].session).inverse().translation();
  PlanOptions options;
  options.tracker_position_m = {tracker.x(), tracker.y(), tracker.z()};
  options.acceptance_angle = arm.acceptance_angle;
  return options;
}

struct Figures {
  double median = 0.0;
  std::map<std::string, double> plan;  // by criterion
};

// For K: the median of 20 random draws and each criterion's plan, held-out RMS in mm (printed).
Figures Compare(const Arm& arm, int K) {
  const CandidatePool pool = ParseCandidatePool(DatasetToCsv(arm.pool), arm.name + " even rows", arm.nominal);
  const PlanOptions defaults = TrackerOfTheData(arm);
  const PlanningProblem problem = PreparePlanning(arm.nominal, pool, defaults);
  std::printf("%s: pool %zu rows, %zu meet the constraints (tracker at %.3f %.3f %.3f m);", arm.name.c_str(),
              pool.q.size(), problem.feasible.size(), defaults.tracker_position_m[0], defaults.tracker_position_m[1],
              defaults.tracker_position_m[2]);
  for (const auto& [why, count] : problem.rejected) std::printf(" %s %d;", why.c_str(), count);
  std::printf(" %zu identifiable parameters\n", problem.model.names.size());
  Figures f;
  if (problem.feasible.size() < static_cast<size_t>(2 * K)) {
    ADD_FAILURE() << arm.name << ": " << problem.feasible.size() << " feasible pool rows for K = " << K;
    return f;
  }
  Rng rng(2026 + K);
  std::vector<double> draws;
  for (int d = 0; d < 20; ++d) {
    std::vector<int> rows = problem.feasible;
    for (int i = 0; i < K; ++i) std::swap(rows[i], rows[i + rng.NextU64() % (rows.size() - i)]);
    rows.resize(K);
    draws.push_back(HeldOutRms(arm, rows));
  }
  std::sort(draws.begin(), draws.end());
  f.median = 0.5 * (draws[9] + draws[10]);
  std::printf("%s, K = %d: 20 random draws: median %.4f mm (min %.4f, max %.4f)\n", arm.name.c_str(), K, f.median,
              draws.front(), draws.back());
  for (const std::string criterion : {"D", "A", "I"}) {
    PlanOptions options = defaults;
    options.criterion = criterion;
    f.plan[criterion] = HeldOutRms(arm, PlanMeasurements(arm.nominal, pool, K, options).rows);
    std::printf("%s, K = %d: %s-optimal plan: held-out RMS %.4f mm%s\n", arm.name.c_str(), K, criterion.c_str(),
                f.plan[criterion], criterion == PlanOptions().criterion ? " (the default)" : "");
  }
  std::fflush(stdout);
  return f;
}

TEST(PlanRealData, Ur10SeriesC) {
  KINCAL_UR10_DATA_OR_SKIP();
  TempDir dir;
  const std::string path = dir.path("c.csv");
  std::string err;
  ASSERT_EQ(RunUr10Converter("'" + Ur10Series(kUr10C) + "' --split even-odd --out '" + path + "'", dir, &err), 0)
      << err;
  const Dataset all = ReadDataset(path);
  Arm arm{"ur10_ipa2021 C", ReadRobotFile(SourcePath("examples/robots/ur10_joint_errors.yaml")),
          all.Subset(Split::kTrain), all.Subset(Split::kTest)};
  arm.nominal.joint_errors = JointErrors();  // geometry
  const Figures k30 = Compare(arm, 30);
  EXPECT_LE(k30.plan.at(PlanOptions().criterion), k30.median);
  Compare(arm, 60);
}

TEST(PlanRealData, Irb120FaroReflector1) {
  // The data do not say where the reflector points (it faces the tracker off the flange's axis in every
  // pose): no acceptance angle; range and line of sight are checked.
  Arm arm{"irb120_faro SMR1", Irb120FaroNominal(), {}, {}, M_PI};
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120FaroSplit(SharedDataPath("irb120_faro"), 1, &arm.pool, &arm.test),
                                  "no ../shared/data/irb120_faro");
  for (int K : {30, 60}) {
    const Figures f = Compare(arm, K);
    EXPECT_LE(f.plan.at(PlanOptions().criterion), f.median) << "K = " << K;
  }
}

}  // namespace
}  // namespace kincal::testing
