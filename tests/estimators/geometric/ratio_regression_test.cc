// The ratio_regression estimator alone and in a pipeline.
#include "estimators/ratio_regression/ratio_regression_estimator.h"

#include <gtest/gtest.h>

#include "tests/estimators/geometric/seed_fixture.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

double MaxRelativeRatioError(const Robot& a, const Robot& b) {
  return ((a.drives->ratio - b.drives->ratio).array() / b.drives->ratio.array()).abs().maxCoeff();
}

// Alone, from the nominal robot: it refits the axes itself, writes the truth's ratios and nothing else.
TEST(RatioRegression, AloneGivesTheRatiosAndKeepsTheGeometry) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  Robot identified;
  const EstimationReport report =
      RatioRegressionEstimator().Estimate(nominal, SeedSweeps(nominal, truth, 0.0, 1), &identified);
  EXPECT_LT(MaxRelativeRatioError(identified, truth), 1e-12);
  EXPECT_EQ(identified.model().Parameters(), nominal.model().Parameters());
  ASSERT_EQ(report.parameters.size(), 6u);
  for (const auto& p : report.parameters) EXPECT_TRUE(p.free) << p.name;
  EXPECT_EQ(report.details["motor_angle_from"], "encoder counts");
  EXPECT_EQ(report.details["joints"].size(), 6u);
}

// Without encoder counts the motor angle is the one the controller commanded (K_controller q). The joint
// actually went to the rounded count, so the encoder's quantization now enters: one count is
// 2 pi / (2048 K) = 3.8e-7 rad (joint 1) to 7.4e-7 rad (joint 6) of joint angle, a uniform +-0.5-count
// error per stop, and over 20 stops 2 deg apart (sum of squared deviations 0.81 rad^2) the slope's
// relative standard deviation is (count / sqrt 12) / 0.90 rad = 1.2e-7 (joint 1) to 2.4e-7 (joint 6).
// With counts (the test above) the error is at rounding level.
TEST(RatioRegression, WithoutEncodersUsesTheCommandedMotorAngle) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  Dataset data = SeedSweeps(nominal, truth, 0.0, 1);
  for (auto& m : data.rows) m.encoders.clear();
  Robot identified;
  const EstimationReport report = RatioRegressionEstimator().Estimate(nominal, data, &identified);
  const double error = MaxRelativeRatioError(identified, truth);
  std::printf("ratios from commanded angles: largest relative error %.3g\n", error);
  EXPECT_LT(error, 1e-6);  // 4 standard deviations of the worst joint
  EXPECT_GT(error, 1e-9);  // and the quantization does show
  EXPECT_EQ(report.details["motor_angle_from"], "commanded angles x controller ratio");
}

// As a later stage the start robot's ratios already differ from the controller's: the regression is
// stated relative to the start (K = K_start / slope), so running it twice changes nothing.
TEST(RatioRegression, IsIdempotentInAPipeline) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  const Dataset data = SeedSweeps(nominal, truth, 10e-6, 3);
  Robot once, twice;
  const YAML::Node none;
  RunPipeline({"ratio_regression"}, {none}, nominal, data, &once);
  RunPipeline({"ratio_regression", "ratio_regression"}, {none, none}, nominal, data, &twice);
  EXPECT_LT(MaxRelativeRatioError(twice, once), 1e-12);
  EXPECT_GT(MaxRelativeRatioError(once, truth), 1e-5);  // noise does show
}

TEST(RatioRegression, JointsNeverSweptKeepTheirRatio) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  Dataset data = SeedSweeps(nominal, truth, 0.0, 1);
  std::vector<Measurement> kept;
  for (const auto& m : data.rows) {
    if (m.sweep != 2) kept.push_back(m);
  }
  data.rows = kept;
  Robot identified;
  const EstimationReport report = RatioRegressionEstimator().Estimate(nominal, data, &identified);
  EXPECT_EQ(identified.drives->ratio[1], nominal.drives->ratio[1]);
  EXPECT_NEAR(identified.drives->ratio[0], truth.drives->ratio[0], 1e-9);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("joint 2 was never swept"), std::string::npos);
  EXPECT_EQ(report.fixed_parameters, std::vector<std::string>{"ratio_2"});
}

}  // namespace
}  // namespace kincal::testing
