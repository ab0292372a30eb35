// Prediction uncertainty (estimators/error_model/prediction_uncertainty.h): the predicted sd of a row is
// the spread of the identified robot's prediction there over repeated experiments. Monte Carlo on the
// seed's arm: 40 independent noisy datasets, each fitted; at fixed new poses the mean squared error of the
// prediction against the truth must match the mean sd^2 that (1) reports.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

TEST(PredictionUncertainty, PredictedSdMatchesTheMonteCarloSpreadOfPredictions) {
  const Robot nominal = SeedNominal();
  Robot truth = SeedTruth();
  truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(1.8, -0.6, 0.4), Eigen::Vector3d(0.3, -0.2, 2.0)));
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = 40;
  so.seed = 999;
  const Dataset targets = Simulate(nominal, truth, so);  // noise-free: the truth's positions
  so.poses = 60;
  so.noise_sigma = 100e-6;
  const int trials = 40;
  std::vector<double> mse(targets.rows.size(), 0.0), mean_var(targets.rows.size(), 0.0);
  double sigma_sum = 0.0;
  for (int t = 0; t < trials; ++t) {
    so.seed = 100 + t;
    const Dataset data = Simulate(nominal, truth, so);
    Robot identified;
    const EstimationReport report = Estimators().Create("least_squares")->Estimate(nominal, data, &identified);
    ASSERT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
    const PredictionCovariance cov = PredictionCovariance::FromJson(report.details.at("prediction_covariance"));
    sigma_sum += cov.sigma;
    const std::vector<double> sd = PredictionSd(identified, nominal, targets, cov);
    const std::vector<Eigen::Vector3d> p = PredictMarkers(nominal, identified, targets);
    for (size_t i = 0; i < targets.rows.size(); ++i) {
      mse[i] += (p[i] - targets.rows[i].p).squaredNorm() / trials;
      mean_var[i] += sd[i] * sd[i] / trials;
    }
  }
  EXPECT_NEAR(sigma_sum / trials, 100e-6, 10e-6);  // the noise estimate behind C
  double ratio = 0.0;
  for (size_t i = 0; i < targets.rows.size(); ++i) ratio += mse[i] / mean_var[i] / targets.rows.size();
  // 40 trials: the mean over 40 poses of a ratio of chi-square-like averages; 1 within about 15 %.
  EXPECT_GT(ratio, 0.75);
  EXPECT_LT(ratio, 1.3);
  std::printf("mean over poses of MSE / sd^2: %.3f\n", ratio);
}

}  // namespace
}  // namespace kincal::testing
