// The geometric + ratio_regression identification over many noise seeds: unbiased, and its reported
// standard deviations match the spread of the estimates.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "tests/estimators/geometric/seed_fixture.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

struct Sample {
  std::vector<double> z;       // (estimate - truth) / reported stddev, one per run
  std::vector<double> error;   // estimate - truth
  std::vector<double> stddev;  // reported
};

void RunMonteCarlo(const std::string& stddev_method, int runs, double noise, std::map<std::string, Sample>* out) {
  const Robot nominal = SeedNominal();
  const Robot truth = SeedTruth();
  for (int s = 1; s <= runs; ++s) {
    const Dataset data = SeedSweeps(nominal, truth, noise, 1000 + s);
    Robot identified;
    const auto reports = Identify(nominal, data, &identified, "{stddev: " + stddev_method + "}");
    for (const auto& report : reports) {
      for (const auto& p : report.parameters) {
        if (!p.free) continue;
        const double truth_value = p.name.rfind("ratio_", 0) == 0 ? truth.drives->ratio[std::stoi(p.name.substr(6)) - 1]
                                                                  : truth.model().Parameter(p.name);
        Sample& sample = (*out)[p.name];
        sample.error.push_back(p.value - truth_value);
        sample.stddev.push_back(p.stddev);
        sample.z.push_back((p.value - truth_value) / p.stddev);
      }
    }
  }
}

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / v.size();
}

double Rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / v.size());
}

// Runs at tracker-like noise (10 um per axis). For each of the 33 identified parameters the z-scores
// (estimate - truth) / reported stddev must look standard normal:
//  - unbiased: |mean z| < 4 / sqrt(runs) (4 standard errors: with 33 parameters a false alarm has
//    probability about 0.2 %; the seeds are fixed, so the test is deterministic);
//  - calibrated: the RMS of z, whose standard error is about 1 / sqrt(2 runs), within 1 +- 5 standard
//    errors (0.2 for 300 runs, 0.35 for 100).
void CheckStatistics(const std::string& stddev_method, int runs) {
  std::map<std::string, Sample> samples;
  RunMonteCarlo(stddev_method, runs, 10e-6, &samples);
  ASSERT_EQ(samples.size(), 33u);  // 18 table entries, 6 base, 3 tool position, 6 ratios
  for (const auto& [name, s] : samples) {
    SCOPED_TRACE(name);
    ASSERT_EQ(static_cast<int>(s.z.size()), runs);
    const double mean_z = Mean(s.z);
    const double rms_z = Rms(s.z);
    std::printf("%-11s bias/stddev %+.3f  rms z %.3f  empirical sd %.3g  mean reported %.3g\n", name.c_str(), mean_z,
                rms_z, Rms(s.error), Mean(s.stddev));
    EXPECT_LT(std::abs(mean_z), 4.0 / std::sqrt(runs));
    EXPECT_NEAR(rms_z, 1.0, 5.0 / std::sqrt(2.0 * runs));
  }
}

TEST(GeometricStatistics, PropagatedStandardDeviationsMatchTheSpread) { CheckStatistics("propagation", 300); }

TEST(GeometricStatistics, BootstrapStandardDeviationsMatchTheSpread) { CheckStatistics("bootstrap", 100); }

}  // namespace
}  // namespace kincal::testing
