#pragma once
// The benchmark programs also run as ctest tests (bench/CMakeLists.txt), which check that they compile,
// run and pass their own checks, not their figures: there KINCAL_BENCH_SMOKE=1 shrinks their largest
// problems (the same code paths at a tenth of the size or less). Run by hand, they measure at full size.
#include <cstdlib>
#include <cstring>

namespace kincal {

inline bool BenchSmoke() {
  const char* v = std::getenv("KINCAL_BENCH_SMOKE");
  return v != nullptr && *v != '\0' && std::strcmp(v, "0") != 0;
}

// `full` when measuring, `smoke` in a ctest run.
inline int BenchSize(int full, int smoke) { return BenchSmoke() ? smoke : full; }

}  // namespace kincal
