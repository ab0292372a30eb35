#pragma once
// Series A of ../shared/data/ur10_ipa2021 for the benchmarks that fit it, or the benchmark skipped: the ctest
// smoke run (bench/CMakeLists.txt) reads "no ../shared/data" as skipped, anything else as failed.
#include <cstdlib>
#include <string>

#include <benchmark/benchmark.h>

#include "framework/dataset.h"
#include "tests/estimators/ur10_ipa2021.h"

namespace kincal::bench {

inline bool LoadSeriesAOrSkip(benchmark::State& state, Dataset* all) {
  if (testing::LoadUr10Series(testing::SharedDataPath("ur10_ipa2021/Series_A/measurements_grid.csv"), all)) return true;
  const char* required = std::getenv("KINCAL_REQUIRE_DATA");
  state.SkipWithError(required != nullptr && std::string(required) == "1"
                          ? "KINCAL_REQUIRE_DATA=1 and ../shared/data/ur10_ipa2021 is missing"
                          : "no ../shared/data/ur10_ipa2021");
  return false;
}

}  // namespace kincal::bench
