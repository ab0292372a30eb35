#pragma once
// Estimator conformance kit, for the authors of an estimator (a plugin's or kincal's own): on data
// simulated from a known truth (robot/simulator.h), the estimator recovers the truth, and it never ends
// worse than it started. Header-only, on GoogleTest; each check returns a ::testing::AssertionResult
// that says what failed, for EXPECT_TRUE.
//
//   #include "testing/estimator_conformance.h"
//   TEST(MyEstimator, RecoversTheTruth) {
//     EXPECT_TRUE(kincal::testing::RecoversSimulatedTruth(MyEstimator(), nominal, truth));
//   }
//
// Lengths in m. Keep the datasets small (tens of poses): the kit runs in every build of a plugin's tests.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/robot.h"
#include "robot/simulator.h"

namespace kincal::testing {

// `poses` configurations uniform within the joint limits (the simulator's "random" protocol, Rng(seed)),
// measured on `truth` without noise and read back by `nominal` (the controller).
inline Dataset SimulatedPoses(const Robot& nominal, const Robot& truth, int poses, uint64_t seed) {
  SimulatorOptions options;
  options.protocol = "random";
  options.poses = poses;
  options.seed = seed;
  return Simulate(nominal, truth, options);
}

// The position errors (m) of `identified` on `poses` fresh poses of the truth (seed apart from the
// training rows'), read by `nominal`: how well the identified robot predicts the real one.
inline ErrorStats HeldOutErrors(const Robot& nominal, const Robot& truth, const Robot& identified, int poses,
                                uint64_t seed) {
  return EvaluatePredictions(nominal, identified, SimulatedPoses(nominal, truth, poses, seed)).position_stats;
}

// The estimator, started from `nominal` on `poses` noise-free poses of `truth` (seed `seed`):
//  - does not fail (a status other than kFailed) and reports finite residuals;
//  - never ends worse than it starts: its final residual RMS is at most its initial one, and the
//    identified robot's own residual RMS on the training rows (computed apart from the estimator) at
//    most the start's, both to 1e-9 relative;
//  - recovers the truth: the largest held-out position error (100 fresh poses) is below `tolerance` m.
// `nominal` and `truth` must differ only by what the estimator identifies.
inline ::testing::AssertionResult RecoversSimulatedTruth(const Estimator& estimator, const Robot& nominal,
                                                         const Robot& truth, double tolerance = 1e-6,
                                                         int poses = 60, uint64_t seed = 1) {
  const Dataset data = SimulatedPoses(nominal, truth, poses, seed);
  Robot identified;
  const EstimationReport report = estimator.Estimate(nominal, data, &identified);
  if (report.status == EstimationStatus::kFailed)
    return ::testing::AssertionFailure() << estimator.name() << " failed: " << report.message;
  if (!std::isfinite(report.initial_rms) || !std::isfinite(report.final_rms))
    return ::testing::AssertionFailure() << estimator.name() << " reports residuals that are not finite: "
                                         << report.BriefReport();
  if (report.final_rms > report.initial_rms * (1 + 1e-9))
    return ::testing::AssertionFailure() << estimator.name() << " ends worse than it starts: "
                                         << report.BriefReport();
  const double start = EvaluatePredictions(nominal, nominal, data).position_stats.rms;
  const double end = EvaluatePredictions(nominal, identified, data).position_stats.rms;
  if (end > start * (1 + 1e-9))
    return ::testing::AssertionFailure() << estimator.name() << "'s robot predicts the training rows worse than the "
                                         << "start: RMS " << end << " m against " << start << " m";
  const ErrorStats held_out = HeldOutErrors(nominal, truth, identified, 100, seed + 1000);
  if (!(held_out.max <= tolerance))
    return ::testing::AssertionFailure() << estimator.name() << " misses the truth: held-out max error "
                                         << held_out.max << " m (tolerance " << tolerance << " m); "
                                         << report.BriefReport();
  return ::testing::AssertionSuccess();
}

}  // namespace kincal::testing
