#pragma once
// Shared by the compensator tests: the seed's arm as the controller believes it (Table 1, nominal ratios)
// and as it is (Table 2, identified ratios), and targets it reaches.
#include <map>
#include <memory>
#include <string>

#include "compensators/common/random_targets.h"
#include "compensators/compensator.h"
#include "tests/support/test_util.h"

namespace kincal::testing {

struct SeedArm {
  Robot nominal = SeedNominal();
  Robot identified = SeedTruth();
};
inline const SeedArm& Arm() {
  static const SeedArm arm;
  return arm;
}

// Reachable targets away from singular configurations (sigma_min / sigma_max >= 0.01 with position rows in
// units of 0.5 m; the median over the seed arm's joint space is 0.05), with the controller's nominal
// solution as the seed.
inline RandomTargets WellConditionedTargets(int count, uint64_t seed, bool orientation = true) {
  RandomTargetOptions o;
  o.count = count;
  o.seed = seed;
  o.orientation = orientation;
  o.min_sigma_ratio = 0.01;
  return MakeRandomTargets(Arm().nominal, Arm().identified, o);
}

// Options the suites use: the defaults (kept as a hook for methods whose defaults are too costly for a
// test process).
inline std::string TestOptions(const std::string& name) {
  (void)name;
  return "{}";
}

// A compensator from the registry with TestOptions, prepared on the seed arm once per process.
inline const Compensator& Prepared(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Compensator>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = Compensators().Create(name, YAML::Load(TestOptions(name)));
    slot->Prepare(Arm().nominal, Arm().identified);
  }
  return *slot;
}

}  // namespace kincal::testing
