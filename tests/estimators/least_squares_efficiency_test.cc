// Statistical efficiency of least_squares by Monte Carlo: the same 40 poses measured 200 times
// with fresh Gaussian noise. For each identifiable parameter, the RMS error over the trials divided by
// the predicted standard deviation (the reported one, sigma^2 (J^T J)^-1: the Cramer-Rao bound) must be
// close to 1: their mean within [0.95, 1.05], none outside [0.8, 1.2]. With 200 trials one ratio
// scatters by about 1 / sqrt(400) = 5 %, so [0.8, 1.2] is a 4-sigma band.
#include <cmath>
#include <cstdio>
#include <map>

#include "framework/random.h"
#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

TEST(LeastSquaresEfficiency, RmsErrorMatchesTheCramerRaoBound) {
  constexpr int kTrials = 200;
  const double noise = 50e-6;
  const SimulatedCase c = RandomPoseCase(40, 0.0, 31);
  const auto estimator = Estimators().Create("least_squares");

  struct Tally {
    double truth = 0.0, sum_error = 0.0, sum_error2 = 0.0, sum_var = 0.0;
    int count = 0;
  };
  std::map<std::string, Tally> tally;
  std::vector<std::string> order;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Dataset noisy = WithPositionNoise(c.data, noise, Rng::Derive(777, trial));
    Robot identified;
    const EstimationReport report = estimator->Estimate(c.nominal, noisy, &identified);
    ASSERT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
    for (const auto& p : report.parameters) {
      if (!p.free) continue;
      if (!tally.count(p.name)) order.push_back(p.name);
      Tally& t = tally[p.name];
      t.truth = TruthValue(c.truth, p.name);
      const double e = p.value - t.truth;
      t.sum_error += e;
      t.sum_error2 += e * e;
      t.sum_var += p.stddev * p.stddev;
      ++t.count;
    }
  }
  ASSERT_EQ(order.size(), 33u);
  double sum_ratio = 0.0;
  std::printf("%-12s %14s %14s %14s %8s %8s\n", "parameter", "truth", "RMS error", "predicted sd", "bias/sd", "RMS/sd");
  for (const auto& name : order) {
    const Tally& t = tally[name];
    ASSERT_EQ(t.count, kTrials) << name;
    const double rms = std::sqrt(t.sum_error2 / t.count);
    const double predicted = std::sqrt(t.sum_var / t.count);
    const double ratio = rms / predicted;
    sum_ratio += ratio;
    std::printf("%-12s %14.8g %14.4g %14.4g %8.3f %8.3f\n", name.c_str(), t.truth, rms, predicted,
                t.sum_error / t.count / predicted, ratio);
    EXPECT_GE(ratio, 0.8) << name;
    EXPECT_LE(ratio, 1.2) << name;
  }
  const double mean_ratio = sum_ratio / order.size();
  std::printf("mean RMS/sd over %zu parameters: %.4f (%d trials, %zu poses, noise %.0f um per axis)\n", order.size(),
              mean_ratio, kTrials, c.data.rows.size(), noise * 1e6);
  EXPECT_GE(mean_ratio, 0.95);
  EXPECT_LE(mean_ratio, 1.05);
}

}  // namespace
}  // namespace kincal::testing
