// Joint-level fits beside the geometry fit, one process, CPU seconds of each in the same run, on
// ur10_ipa2021 series A (even rows fitted: 5,956; odd rows held out for the audit), least_squares with
// max_iterations 200:
//   geometry        ur10_dh.yaml with a 100 mm tool (the geometry row of docs/guide/real_data.md)
//   prior           examples/robots/ur10_joint_errors.yaml, every term free, `prior: on`
//   select          the same file with `select: true` (23 nested candidates, 5 folds, the chosen one refit)
//   select_audit    select, then every candidate fitted on the training rows and scored on the held-out ones
//                   (`kincal identify --select --audit`), once
// Counters: each one's CPU seconds and its ratio to geometry (targets: prior <= 3, select <= 4, select_audit
// <= 30). The ctest smoke run (a tiny --benchmark_min_time) fits every 20th training row and audits 3
// candidates: it checks that the program runs, not the figures. Skips without ../shared/data.
//   ./build/bench/kincal_joint_level_speed_bench
#include <ctime>
#include <cstdlib>
#include <cstring>
#include <string>

#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "estimators/selection/selection_audit.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "bench/ur10_series_a.h"
#include "tests/estimators/ur10_ipa2021.h"

namespace kincal {
namespace {

bool smoke = false;  // set by main from --benchmark_min_time

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// CPU seconds of one least_squares estimate, the robot it identified into *identified.
double TimeFit(const Robot& start, const Dataset& train, const YAML::Node& options, Robot* identified) {
  const auto estimator = Estimators().Create("least_squares", options);
  const double t0 = CpuSeconds();
  const EstimationReport report = estimator->Estimate(start, train, identified);
  benchmark::DoNotOptimize(report.final_rms);
  return CpuSeconds() - t0;
}

void BM_JointLevelSeriesA(benchmark::State& state) {
  Dataset all;
  if (!bench::LoadSeriesAOrSkip(state, &all)) return;
  std::vector<int> even, odd;
  for (size_t i = 0; i < all.rows.size(); ++i) (i % 2 == 0 ? even : odd).push_back(static_cast<int>(i));
  if (smoke) {
    std::vector<int> few;
    for (size_t i = 0; i < even.size(); i += 20) few.push_back(even[i]);
    even = few;
  }
  const Dataset train = all.SelectRows(even), heldout = all.SelectRows(odd);
  const Robot geometry = testing::Ur10Rich(0);
  const Robot rich = testing::LoadExampleRobot("ur10_joint_errors.yaml");
  YAML::Node base;
  base["max_iterations"] = 200;
  YAML::Node prior = YAML::Clone(base), select = YAML::Clone(base);
  prior["prior"] = "on";
  select["select"] = true;
  for (auto _ : state) {
    Robot g, p, s;
    const double t_geometry = TimeFit(geometry, train, base, &g);
    const double t_prior = TimeFit(rich, train, prior, &p);
    const double t_select = TimeFit(rich, train, select, &s);
    // The audit as identify runs it after the selection: every candidate (3 in the smoke run).
    const EstimatorFactory create = [](const YAML::Node& o) { return Estimators().Create("least_squares", o); };
    Robot audit_start = rich;
    if (smoke) audit_start.joint_errors.terms.resize(2);
    const double t0 = CpuSeconds();
    const std::vector<CandidateHeldOut> audit =
        AuditCandidates(create, AuditFitOptions(select), audit_start, rich, train, heldout);
    const double t_audit = t_select + CpuSeconds() - t0;
    benchmark::DoNotOptimize(audit);
    state.counters["rows"] = static_cast<double>(train.rows.size());
    state.counters["geometry_s"] = t_geometry;
    state.counters["prior_s"] = t_prior;
    state.counters["select_s"] = t_select;
    state.counters["select_audit_s"] = t_audit;
    state.counters["prior_x"] = t_prior / t_geometry;
    state.counters["select_x"] = t_select / t_geometry;
    state.counters["select_audit_x"] = t_audit / t_geometry;
    state.counters["audit_candidates"] = static_cast<double>(audit.size());
    // What the fits hold out (mm): the figures of docs/guide/real_data.md, a check that nothing moved.
    state.counters["geometry_held_out_mm"] = EvaluatePredictions(geometry, g, heldout).position_stats.rms * 1e3;
    state.counters["prior_held_out_mm"] = EvaluatePredictions(rich, p, heldout).position_stats.rms * 1e3;
    state.counters["select_held_out_mm"] = EvaluatePredictions(rich, s, heldout).position_stats.rms * 1e3;
  }
}
BENCHMARK(BM_JointLevelSeriesA)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime();

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--benchmark_min_time=", 21) == 0 && std::atof(argv[i] + 21) < 0.01)
      kincal::smoke = true;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
