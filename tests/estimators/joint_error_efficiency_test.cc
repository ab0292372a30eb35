// Statistical efficiency of the joint error coefficients, as least_squares_efficiency_test.cc
// checks it for geometry: the same 120 poses measured 150 times with fresh noise; for every identifiable
// coefficient the RMS error over the trials divided by the reported standard deviation must be close to 1
// (mean within [0.95, 1.05]; each within [0.75, 1.25], a 3.5-sigma band for 150 trials).
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "tests/estimators/joint_error_fixture.h"

namespace kincal::testing {
namespace {

// As tests/estimators/least_squares_efficiency_test.cc for geometry: RMS error over trials / reported sd.
TEST(JointErrorModel, CoefficientsAreEstimatedAtTheCramerRaoBound) {
  constexpr int kTrials = 150;
  const double noise = 30e-6;
  const JointErrorCase c = MakeCase(120, 33);
  const auto estimator = Estimators().Create("least_squares");
  std::map<std::string, std::array<double, 3>> tally;  // sum error^2, sum var, count
  for (int trial = 0; trial < kTrials; ++trial) {
    const Dataset noisy = WithPositionNoise(c.data, noise, Rng::Derive(555, trial));
    Robot identified;
    const EstimationReport report = estimator->Estimate(c.nominal, noisy, &identified);
    ASSERT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
    for (const auto& p : report.parameters) {
      if (!p.free || p.name.find('_') == std::string::npos) continue;
      const std::string type = p.name.substr(0, p.name.find('_'));
      if (type != "gravity" && type != "harmonic" && type != "backlash" && type != "approach") continue;
      const double e = p.value - TruthCoefficient(c.truth, p.name);
      auto& t = tally[p.name];
      t[0] += e * e;
      t[1] += p.stddev * p.stddev;
      t[2] += 1;
    }
  }
  ASSERT_FALSE(tally.empty());
  double sum = 0.0;
  for (const auto& [name, t] : tally) {
    ASSERT_EQ(t[2], kTrials) << name;
    const double ratio = std::sqrt(t[0] / t[1]);
    sum += ratio;
    std::printf("%-24s RMS/sd %.3f\n", name.c_str(), ratio);
    EXPECT_GE(ratio, 0.75) << name;
    EXPECT_LE(ratio, 1.25) << name;
  }
  const double mean = sum / tally.size();
  std::printf("mean RMS/sd over %zu joint error coefficients: %.4f (%d trials)\n", tally.size(), mean, kTrials);
  EXPECT_GE(mean, 0.95);
  EXPECT_LE(mean, 1.05);
}

}  // namespace
}  // namespace kincal::testing
