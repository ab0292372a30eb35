// Model selection (`select: true`, estimators/selection/model_selection.h) on the case of the target:
// ur10_ipa2021 series A, even rows (5,955 training rows), ur10_dh.yaml with a 100 mm tool and the richest
// file (gravity 2-5, harmonic 1 and 2, backlash and approach on every joint: 23 nested candidates, 5
// folds). Target: <= 10 s on one core for the whole estimate (cross-validation and the refit of the chosen
// model); the CPU time is the figure (the machine may be shared). Skips without ../shared/data.
//   ./build/bench/kincal_model_selection_bench
#include <cstdlib>
#include <string>

#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "bench/ur10_series_a.h"
#include "tests/estimators/ur10_ipa2021.h"

namespace kincal {
namespace {

void BM_SelectSeriesA(benchmark::State& state) {
  Dataset all;
  if (!bench::LoadSeriesAOrSkip(state, &all)) return;
  std::vector<int> even;
  for (size_t i = 0; i < all.rows.size(); i += 2) even.push_back(static_cast<int>(i));
  const Dataset train = all.SelectRows(even);
  const Robot start = testing::Ur10Rich(22);
  YAML::Node options;
  options["select"] = true;
  options["max_iterations"] = 200;
  const auto estimator = Estimators().Create("least_squares", options);
  for (auto _ : state) {
    Robot identified;
    const EstimationReport report = estimator->Estimate(start, train, &identified);
    benchmark::DoNotOptimize(report.final_rms);
    state.counters["rows"] = static_cast<double>(train.rows.size());
    state.counters["iterations_final_fit"] = report.iterations;
  }
}
BENCHMARK(BM_SelectSeriesA)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime();

}  // namespace
}  // namespace kincal

BENCHMARK_MAIN();
