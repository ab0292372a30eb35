#pragma once
// TEST DOUBLES for the study tests. They are NOT registered in the library's registries: the tests pass
// them to the study through MethodRegistries, so that studies with non-trivial estimators and compensators
// can be run in this branch, whatever the library registers.
//   estimators:   none (the library's), base_kabsch (fits the base transform only, Kabsch/Umeyama on the
//                 predicted and measured marker positions), oracle (returns the truth robot it was given),
//                 throws (always throws, like an estimator given data it cannot use), nan (returns a NaN
//                 parameter)
//   compensators: none (the library's), jacobian_ik (damped Gauss-Newton on the identified robot, with the
//                 convergence histories filled), throws (throws an int), nan (returns NaN joint angles)
#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "studies/study.h"

namespace kincal::testing {

struct TestRegistries {
  EstimatorRegistry estimators;
  CompensatorRegistry compensators;
  MethodRegistries view() const { return {&estimators, &compensators}; }
};

// `truth` is what the oracle estimator returns. The doubles that return NaN or throw from a compensator are
// registered only `with_failures`.
TestRegistries MakeTestRegistries(const Robot& truth, bool with_failures = false);

}  // namespace kincal::testing
