// The checks every error-model estimator passes (error_model_fixture.h): noise-free data gives the truth
// to rounding level, noisy data gives it within the reported standard deviations, sessions, markers and
// orientations are identified, and all estimators agree with each other.
#include <cmath>
#include <cstdio>
#include <map>

#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

TEST_P(ErrorModelEstimatorTest, NoiseFreeDataGivesTheTruthToRoundingLevel) {
  const SimulatedCase c = RandomPoseCase(60, 0.0, 21);
  EstimationReport report;
  const Robot identified = Run(c.data, c.nominal, &report);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  const std::vector<std::string> unidentifiable = {"alpha_1", "a_1", "theta_1", "d_1", "theta_6", "d_6"};
  EXPECT_EQ(report.fixed_parameters, unidentifiable);
  // Table 2's first row and last offsets equal Table 1's, so every free parameter has a unique true value.
  int free = 0;
  double worst = 0.0;
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    ++free;
    const double truth = TruthValue(c.truth, p.name);
    worst = std::max(worst, std::abs(p.value - truth) / ParameterSize(p));
    EXPECT_LE(std::abs(p.value - truth), 1e-11 * ParameterSize(p)) << p.name << " " << p.value << " vs " << truth;
  }
  EXPECT_EQ(free, 33);
  EXPECT_LT(report.final_rms, 1e-12);
  const ErrorStats heldout = HeldOutErrors(c, identified, 300, 99);
  EXPECT_LT(heldout.max, 1e-11) << "held-out max " << heldout.max;
  std::printf("%s, noise-free: %s\n  largest parameter error %.3g (m, rad, relative for ratios), held-out max %.3g m\n",
              GetParam().c_str(), report.BriefReport().c_str(), worst, heldout.max);
}

TEST_P(ErrorModelEstimatorTest, NoisyDataGivesTheTruthWithinTheReportedStandardDeviations) {
  const double noise = 20e-6;
  const SimulatedCase c = RandomPoseCase(100, noise, 5);
  EstimationReport report;
  const Robot identified = Run(c.data, c.nominal, &report);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    ASSERT_TRUE(std::isfinite(p.stddev)) << p.name;
    EXPECT_LT(std::abs(p.value - TruthValue(c.truth, p.name)), 4.5 * p.stddev) << p.name;
  }
  // sigma from the residuals estimates the noise (267 degrees of freedom: about 4 % scatter).
  const double sigma = report.details["sigma_m"].get<double>();
  EXPECT_NEAR(sigma, noise, 0.15 * noise);
  // Residuals are the noise: RMS of the 3-D error about sqrt(3 (m - p) / m) sigma.
  EXPECT_NEAR(report.final_rms, std::sqrt(3.0) * noise, 0.2 * noise);
  EXPECT_LT(HeldOutErrors(c, identified, 300, 7).rms, 2.0 * noise);
}

TEST_P(ErrorModelEstimatorTest, IdentifiesMarkersSessionBasesAndOrientation) {
  const SimulatedCase c = SessionCase(60, 0.0, 12);
  EstimationReport report;
  const Robot identified = Run(c.data, c.nominal, &report);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  const auto params = ByName(report);
  for (const char* name : {"tool_x", "tool_y", "tool_z"}) EXPECT_FALSE(params.at(name)->free) << name;
  for (const char* name : {"tool_roll", "marker_A_x", "marker_B_z", "session_1_yaw", "session_2_x", "ratio_4"}) {
    EXPECT_TRUE(params.at(name)->free) << name;
  }
  for (const auto& [id, position] : c.truth.markers) {
    EXPECT_LT((identified.markers.at(id) - position).norm(), 1e-11) << id;
  }
  for (int k : {1, 2}) {
    const Eigen::Matrix4d error = identified.session_bases.at(k).matrix() - c.truth.session_bases.at(k).matrix();
    EXPECT_LT(error.cwiseAbs().maxCoeff(), 1e-11) << "session " << k;
  }
  const PredictionErrors errors = EvaluatePredictions(c.nominal, identified, c.data);
  EXPECT_LT(errors.position_stats.max, 1e-11);
  EXPECT_LT(errors.orientation_stats.max, 1e-11);
}

INSTANTIATE_TEST_SUITE_P(ErrorModel, ErrorModelEstimatorTest, ::testing::ValuesIn(kErrorModelEstimators),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// They minimise the same cost, so on the same data they find the same minimum.
TEST(ErrorModelEstimators, AgreeWithEachOtherWithinTheirStandardDeviations) {
  const SimulatedCase c = RandomPoseCase(80, 20e-6, 17);
  EstimationReport reference;
  RunEstimator("least_squares", c.nominal, c.data, &reference, FixtureOptions("least_squares"));
  const auto expected = ByName(reference);
  int compared = 0;
  for (const auto& name : kErrorModelEstimators) {
    if (name == "least_squares") continue;
    EstimationReport report;
    RunEstimator(name, c.nominal, c.data, &report, FixtureOptions(name));
    for (const auto& p : report.parameters) {
      const ParameterEstimate& e = *expected.at(p.name);
      EXPECT_EQ(p.free, e.free) << name << " " << p.name;
      if (!p.free) continue;
      EXPECT_LT(std::abs(p.value - e.value), 0.1 * e.stddev) << name << " " << p.name;
      EXPECT_NEAR(p.stddev, e.stddev, 0.05 * e.stddev) << name << " " << p.name;
    }
    ++compared;
  }
  if (compared == 0) GTEST_SKIP() << "only least_squares is registered";
}

}  // namespace
}  // namespace kincal::testing
