// No error-model fit ends worse than it started (estimators/error_model/error_model_estimation.h): a
// minimiser that ends above the start is caught by the shared sequence, which returns the best iterate
// with a status that is not `converged`; every registered error-model estimator, on a rich joint-level
// file and few rows, ends at or below the data cost of its registered start.
#include <cmath>
#include <cstdio>

#include "estimators/error_model/error_model_estimation.h"
#include "estimators/error_model/prediction_uncertainty.h"
#include "robot/prediction.h"
#include "tests/estimators/joint_error_fixture.h"

namespace kincal::testing {
namespace {

TEST(FitNeverWorse, AMinimizerThatEndsAboveTheStartGivesBackTheBestIterate) {
  const SimulatedCase c = RandomPoseCase(40, 1e-5, 7);
  // Claims convergence after moving every parameter away from the start, further with each run.
  int calls = 0;
  const ErrorModelMinimizer diverging = [&](const PreparedErrorModel&, const RowWeighting&, int, Eigen::VectorXd* x) {
    ++calls;
    x->array() += 1e-3 * calls;
    MinimizerRun run;
    run.status = EstimationStatus::kConverged;
    run.message = "pretends to converge";
    run.iterations = 1;
    return run;
  };
  Robot identified;
  EstimationReport report;
  EstimateErrorModel("diverging", ErrorModelFitOptions(), 10, diverging, c.nominal, c.nominal, c.data,
                     &identified, &report);
  EXPECT_NE(report.status, EstimationStatus::kConverged) << report.message;
  EXPECT_NE(report.message.find("ended above its start"), std::string::npos) << report.message;
  // The best iterate is the registered start: its cost is the report's start cost, not the run's.
  const double start_rms = report.details["registered_start_rms_m"].get<double>();
  EXPECT_NEAR(report.final_rms, start_rms, 1e-12) << report.BriefReport();
  EXPECT_GT(calls, 0);
}

class FitNeverWorseEstimators : public ::testing::TestWithParam<std::string> {};

// Every joint-level term of the fixture's file, 40 rows: more free parameters than the rows carry well.
TEST_P(FitNeverWorseEstimators, EndsAtOrBelowItsRegisteredStart) {
  const JointErrorCase c = MakeCase(40, 3);
  EstimationReport report;
  const Robot identified = RunEstimator(GetParam(), c.nominal, c.data, &report, YAML::Node());
  ASSERT_FALSE(report.details.is_null()) << report.BriefReport();
  const double start_rms = report.details["registered_start_rms_m"].get<double>();
  // The identified robot's own position RMS on the training rows, computed apart from the estimator.
  const double end_rms = EvaluatePredictions(c.nominal, identified, c.data).position_stats.rms;
  std::printf("%s: registered start %.4f mm, end %.4f mm (%s)\n", GetParam().c_str(), start_rms * 1e3, end_rms * 1e3,
              report.BriefReport().c_str());
  EXPECT_LE(end_rms, start_rms * (1 + 1e-9));
  if (report.status == EstimationStatus::kConverged) {
    EXPECT_LE(report.final_rms, start_rms * (1 + 1e-9));
  }
}

// The held-out rows' predicted sd under a rich joint-level file, from 20 rows: the problem that carries
// the covariance frees every term of the file, more than 20 rows (or a doubled 40) have residuals for.
TEST(FitNeverWorse, PredictionSdOfAFewRowsUnderARichFile) {
  const JointErrorCase c = MakeCase(120, 5);
  EstimationReport report;
  const Robot identified = RunEstimator("least_squares", c.nominal, c.data, &report, YAML::Load("{prior: off}"));
  ASSERT_TRUE(report.details.contains("prediction_covariance"));
  const PredictionCovariance cov = PredictionCovariance::FromJson(report.details["prediction_covariance"]);
  Dataset few = c.data;
  few.rows.resize(20);
  std::vector<double> sd;
  ASSERT_NO_THROW(sd = PredictionSd(identified, c.nominal, few, cov));
  ASSERT_EQ(sd.size(), 20u);
  for (double v : sd) EXPECT_TRUE(std::isfinite(v) && v > 0.0) << v;
}

INSTANTIATE_TEST_SUITE_P(Estimators, FitNeverWorseEstimators, ::testing::ValuesIn(kErrorModelEstimators));

}  // namespace
}  // namespace kincal::testing
