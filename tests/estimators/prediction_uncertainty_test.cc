// Prediction uncertainty (estimators/error_model/prediction_uncertainty.h): the predicted sd of a row is
// the spread of the identified robot's prediction there over repeated experiments. Monte Carlo on the
// seed's arm: 40 independent noisy datasets, each fitted; at fixed new poses the mean squared error of the
// prediction against the truth must match the mean sd^2 that (1) reports.
// The model-inadequacy tau of (2), (3) (`cross_validate: true`): zero where the model is right, and where
// the model lacks an effect, the value the same folds give without noise and with exact refits.
#include <algorithm>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
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

// Random poses of the seed's arm in the order of increasing q2, so that the blocked folds hold out slices
// of joint 2's range (the first and last extrapolate beyond the others); `truth` makes the positions.
Dataset SortedByJoint2(const Robot& nominal, const Robot& truth, double noise, uint64_t seed) {
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = 150;
  so.seed = seed;
  so.noise_sigma = noise;
  const Dataset data = Simulate(nominal, truth, so);
  std::vector<int> order(data.rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return data.rows[a].q[1] < data.rows[b].q[1]; });
  return data.SelectRows(order);
}

PredictionCovariance CrossValidatedFit(const Robot& nominal, const Dataset& data) {
  Robot identified;
  const EstimationReport report =
      Estimators().Create("least_squares", YAML::Load("{cross_validate: true}"))->Estimate(nominal, data, &identified);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  return PredictionCovariance::FromJson(report.details.at("prediction_covariance"));
}

// The right model: the folds' held-out errors are what noise and parameters explain, tau ~ 0: within the
// range below a third of the 3-D noise sqrt(3) sigma (a tenth of its variance); per joint beyond the range,
// where a class holds only the few extreme poses of that joint (a handful of rows, whose mean squared
// error scatters by about the noise variance), below the 3-D noise itself.
TEST(PredictionUncertainty, InadequacyIsNearZeroWhenTheModelIsRight) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  const Dataset data = SortedByJoint2(nominal, truth, 50e-6, 7);
  const PredictionCovariance cov = CrossValidatedFit(nominal, data);
  EXPECT_EQ(cov.inadequacy_source, "cross-validation");
  const double sigma_3d = std::sqrt(3.0) * cov.sigma;
  std::printf("right model: sigma_3d %.4f mm, tau %.4f mm, beyond joint 1..n:", sigma_3d * 1e3, cov.inadequacy * 1e3);
  for (double t : cov.inadequacy_beyond) std::printf(" %.4f", t * 1e3);
  std::printf(" mm\n");
  EXPECT_LT(cov.inadequacy, sigma_3d / 3.0);
  ASSERT_EQ(cov.inadequacy_beyond.size(), static_cast<size_t>(nominal.dof()));
  for (double t : cov.inadequacy_beyond) EXPECT_LT(t, sigma_3d);
}

// The model lacks a known effect: the truth turns joint 2 by an extra 2 mrad sin(2 q2) + 1 mrad cos(2 q2)
// (a harmonic error geometry cannot represent), the fit is geometry. Reference, computed independently of
// (3)'s linearised sums: the same blocked folds on the noise-free positions, each fold fitted by the
// estimator itself (nonlinear, to convergence), its held-out 3-D errors beyond the fold's own in-sample
// noise estimate: the unmodelled effect the folds see, without noise. tau from the noisy data must match
// that reference within 25 % (the noise, 50 um, and the linearisation in the CV) on joint 2 beyond the
// range, where the effect shows, and be well above zero there.
TEST(PredictionUncertainty, InadequacyMatchesTheUnmodelledEffectTheFoldsSee) {
  const Robot nominal = SeedNominal();
  Robot truth = SeedTruth();
  JointErrorTerm harmonic;
  harmonic.type = JointErrorTerm::Type::kHarmonic;
  harmonic.joint = 1;
  harmonic.orders = {2};
  truth.joint_errors.terms.push_back(harmonic);
  truth.joint_errors.Bind(truth.model());
  ASSERT_EQ(truth.joint_errors.terms[0].coefficients.size(), 2);
  truth.joint_errors.terms[0].coefficients << 2e-3, 1e-3;
  const Dataset noisy = SortedByJoint2(nominal, truth, 50e-6, 11);
  const Dataset exact = SortedByJoint2(nominal, truth, 0.0, 11);  // the same poses, noise-free
  const PredictionCovariance cov = CrossValidatedFit(nominal, noisy);

  // The reference: per fold, the estimator's own fit on the noise-free training rows.
  const int K = ModelSelectionOptions().folds;
  const std::vector<int> fold = BlockedFolds(exact, K);
  InadequacySample reference;
  for (int k = 0; k < K; ++k) {
    std::vector<int> train_rows, test_rows;
    for (size_t i = 0; i < exact.rows.size(); ++i) (fold[i] == k ? test_rows : train_rows).push_back(static_cast<int>(i));
    const Dataset train = exact.SelectRows(train_rows), test = exact.SelectRows(test_rows);
    Robot identified;
    const EstimationReport report = Estimators().Create("least_squares")->Estimate(nominal, train, &identified);
    const double sigma = report.details.at("prediction_covariance").at("sigma_m").get<double>();
    Eigen::VectorXd lo = train.rows[0].q, hi = lo;
    for (const Measurement& m : train.rows) lo = lo.cwiseMin(m.q), hi = hi.cwiseMax(m.q);
    const PredictionErrors e = EvaluatePredictions(nominal, identified, test);
    for (size_t i = 0; i < test.rows.size(); ++i) {
      std::vector<int> beyond;
      for (int j = 0; j < nominal.dof(); ++j) {
        const double q = test.rows[i].q[j];
        if (q - hi[j] > PredictionCovariance::kJointMargin || lo[j] - q > PredictionCovariance::kJointMargin)
          beyond.push_back(j);
      }
      reference.squared_error.push_back(e.position[i] * e.position[i]);
      reference.expected.push_back(3.0 * sigma * sigma);  // no noise: the parameters' part is 0
      reference.beyond.push_back(beyond);
    }
  }
  const double tau2_ref = EstimateInadequacy(reference, 1), tau_ref = EstimateInadequacy(reference, -1);
  std::printf("unmodelled harmonic on joint 2: tau within range %.4f mm (reference %.4f), beyond joint 2 %.4f mm "
              "(reference %.4f); sigma_3d %.4f mm\n",
              cov.inadequacy * 1e3, tau_ref * 1e3, cov.inadequacy_beyond.at(1) * 1e3, tau2_ref * 1e3,
              std::sqrt(3.0) * cov.sigma * 1e3);
  ASSERT_GT(tau2_ref, 5.0 * std::sqrt(3.0) * 50e-6);  // the effect shows beyond the range: well above noise
  EXPECT_NEAR(cov.inadequacy_beyond.at(1), tau2_ref, 0.25 * tau2_ref);
  EXPECT_NEAR(cov.inadequacy, tau_ref, 0.25 * tau2_ref);
}

}  // namespace
}  // namespace kincal::testing
