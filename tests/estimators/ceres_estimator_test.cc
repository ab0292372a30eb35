// ceres specifics: options, the residual blocks' derivatives (Ceres' own GradientChecker, every block
// layout: geometry, ratios, markers, base, session bases, orientation rows), the linear solver chosen from
// the session structure, ceres::Covariance against the shared covariance, robust loss and weights
// against least_squares (the same minimiser).
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>

#include "estimators/ceres/ceres_estimator.h"
#include "estimators/ceres/error_model_cost.h"
#include "framework/random.h"
#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

TEST(CeresOptions, ReadFromYamlAndRejectBadValues) {
  const CeresOptions o = CeresOptions::FromYaml(YAML::Load(R"(
linear_solver: dense_normal_cholesky
loss: huber
loss_scale: 50um
weights: [1, 2]
num_threads: 2
max_iterations: 7
initial_trust_region_radius: 1e4
fixed: [base]
)"));
  EXPECT_EQ(o.linear_solver, "dense_normal_cholesky");
  EXPECT_EQ(o.weighting.loss, "huber");
  EXPECT_DOUBLE_EQ(o.weighting.loss_scale, 50e-6);
  EXPECT_EQ(o.weighting.weights, (std::vector<double>{1, 2}));
  EXPECT_EQ(o.num_threads, 2);
  EXPECT_EQ(o.max_iterations, 7);
  EXPECT_DOUBLE_EQ(o.initial_trust_region_radius, 1e4);
  EXPECT_EQ(o.error_model.fixed, std::vector<std::string>{"base"});
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  EXPECT_THROW(CeresOptions::FromYaml(YAML::Load("{linear_solvr: dense_qr}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("ceres", YAML::Load("{linear_solver: iterative_schur}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("ceres", YAML::Load("{num_threads: 0}")), std::invalid_argument);
  // Weights must match the rows: a clear error before anything is solved.
  const SimulatedCase c = RandomPoseCase(30, 0.0, 2);
  EstimationReport report;
  EXPECT_THROW(RunEstimator("ceres", c.nominal, c.data, &report, YAML::Load("{weights: [1, 2, 3]}")),
               std::invalid_argument);
  CeresOptions bad;
  bad.weighting.loss = "tukey";
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("tukey"), std::string::npos);
}

// Ceres' GradientChecker differentiates each residual block numerically: it catches a column copied to
// the wrong block or the wrong place in Ceres' row-major layout, for every kind of row.
TEST(CeresErrorModel, ResidualBlockDerivativesMatchCeresGradientChecker) {
  const SimulatedCase c = SessionCase(12, 0.0, 3);
  const ErrorModelProblem problem(c.nominal, c.nominal, c.data, ErrorModelOptions());
  Eigen::VectorXd x = problem.InitialX();
  Rng rng(4);
  for (int i = 0; i < x.size(); ++i) x[i] += 1e-3 * rng.Normal();  // away from any special point
  WorkspacePool pool(problem);
  std::set<std::string> checked;
  for (int row = 0; row < problem.num_rows(); ++row) {
    const std::vector<int> blocks = problem.RowBlocks(row);
    for (int b : blocks) checked.insert(problem.blocks()[b].name);
    ErrorModelRowCost cost(problem, row, blocks, &pool);
    std::vector<const double*> parameters;
    for (int b : blocks) parameters.push_back(x.data() + problem.blocks()[b].offset);
    // Ridders' extrapolation from a 0.1 % step: Ceres' default 1 % step moves a ratio by 1 % and a 2.4 rad
    // session yaw by 0.024 rad, and its tableau then stops at about 1e-3 relative error on some entries
    // (plain central differences of these rows agree with the analytic Jacobian to 1e-10 at any step).
    ceres::NumericDiffOptions nd;
    nd.ridders_relative_initial_step_size = 1e-3;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(&cost, no_manifolds, nd);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters.data(), 1e-6, &results)) << "row " << row << ": " << results.error_log;
  }
  EXPECT_EQ(checked,
            (std::set<std::string>{"geometry", "ratios", "marker:A", "marker:B", "base", "session:1", "session:2"}));
}

// ceres::Covariance of the same residual blocks is (J^T W J)^-1; the shared helper's is sigma^2 times it.
TEST(CeresErrorModel, CeresCovarianceEqualsTheSharedCovariance) {
  const SimulatedCase c = SessionCase(40, 20e-6, 5);
  const PreparedErrorModel prep = PrepareErrorModel(c.nominal, c.nominal, c.data, ErrorModelOptions());
  const ErrorModelProblem& problem = *prep.problem;
  const Eigen::VectorXd x = problem.InitialX();
  const Covariance shared = ComputeCovariance(AccumulateNormalEquations(problem, x), problem.num_parameters());

  CeresErrorModel model(problem, RowWeighting(), x);
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(options);
  std::vector<const double*> blocks;
  for (size_t b = 0; b < problem.blocks().size(); ++b) blocks.push_back(model.block(static_cast<int>(b)));
  std::vector<std::pair<const double*, const double*>> pairs;
  for (const double* a : blocks) {
    for (const double* b : blocks) pairs.emplace_back(a, b);
  }
  ASSERT_TRUE(covariance.Compute(pairs, &model.problem()));
  const int p = problem.num_parameters();
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> ceres_matrix(p, p);
  ASSERT_TRUE(covariance.GetCovarianceMatrix(blocks, ceres_matrix.data()));
  const Eigen::MatrixXd expected = shared.matrix / (shared.sigma * shared.sigma);
  const Eigen::VectorXd d = expected.diagonal().cwiseSqrt().cwiseInverse();
  // Compared as correlations and relative variances: the entries span many orders of magnitude.
  const Eigen::MatrixXd difference = d.asDiagonal() * (Eigen::MatrixXd(ceres_matrix) - expected) * d.asDiagonal();
  EXPECT_LT(difference.cwiseAbs().maxCoeff(), 1e-8);
}

TEST(CeresEstimator, SessionsSelectTheSparseSolverWhichGivesTheDenseAnswer) {
  const SimulatedCase c = SessionCase(90, 20e-6, 7);
  EstimationReport sparse, dense;
  RunEstimator("ceres", c.nominal, c.data, &sparse, YAML::Node());
  RunEstimator("ceres", c.nominal, c.data, &dense, YAML::Load("{linear_solver: dense_qr}"));
  EXPECT_EQ(sparse.details["linear_solver"], "SPARSE_NORMAL_CHOLESKY");
  EXPECT_EQ(dense.details["linear_solver"], "DENSE_QR");
  EXPECT_EQ(sparse.status, EstimationStatus::kConverged) << sparse.BriefReport();
  EXPECT_EQ(dense.status, EstimationStatus::kConverged) << dense.BriefReport();
  const auto expected = ByName(dense);
  int compared = 0;
  for (const auto& p : sparse.parameters) {
    if (!p.free) continue;
    const ParameterEstimate& e = *expected.at(p.name);
    // Both stop on a relative cost change of 1e-14: about 1e-6 standard deviations apart at most.
    EXPECT_LT(std::abs(p.value - e.value), 1e-4 * e.stddev) << p.name;
    ++compared;
  }
  EXPECT_GT(compared, 45);

  // Without sessions nothing is sparse: dense QR.
  const SimulatedCase plain = RandomPoseCase(60, 20e-6, 8);
  EstimationReport report;
  RunEstimator("ceres", plain.nominal, plain.data, &report, YAML::Node());
  EXPECT_EQ(report.details["linear_solver"], "DENSE_QR");
}

// Several threads evaluate the residual blocks, each with a leased workspace: the same solution.
TEST(CeresEstimator, ThreadsGiveTheSameSolution) {
  const SimulatedCase c = SessionCase(90, 20e-6, 9);
  EstimationReport one, two;
  RunEstimator("ceres", c.nominal, c.data, &one, YAML::Node());
  RunEstimator("ceres", c.nominal, c.data, &two, YAML::Load("{num_threads: 2}"));
  EXPECT_EQ(two.status, EstimationStatus::kConverged) << two.BriefReport();
  const auto expected = ByName(one);
  for (const auto& p : two.parameters) {
    if (!p.free) continue;
    EXPECT_LT(std::abs(p.value - expected.at(p.name)->value), 1e-4 * p.stddev) << p.name;
  }
}

// Huber loss and per-row weights define the same minimiser for Ceres and least_squares (IRLS).
TEST(CeresEstimator, RobustLossAndWeightsFindTheLeastSquaresMinimum) {
  SimulatedCase c = RandomPoseCase(150, 10e-6, 41);
  Rng rng(8);
  for (size_t i = 0; i < c.data.rows.size(); i += 15) {
    c.data.rows[i].p += 2e-3 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
  }
  YAML::Node options = YAML::Load("{loss: huber, loss_scale: 0.04mm}");
  for (size_t i = 0; i < c.data.rows.size(); ++i) options["weights"].push_back(0.5 + (i % 4) * 0.5);
  EstimationReport reference, report;
  YAML::Node ls_options = YAML::Clone(options);
  ls_options["parameter_tolerance"] = 1e-12;
  RunEstimator("least_squares", c.nominal, c.data, &reference, ls_options);
  RunEstimator("ceres", c.nominal, c.data, &report, options);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  const auto expected = ByName(reference);
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    const ParameterEstimate& e = *expected.at(p.name);
    EXPECT_LT(std::abs(p.value - e.value), 1e-6 * e.stddev) << p.name;
    EXPECT_NEAR(p.stddev, e.stddev, 1e-6 * e.stddev) << p.name;
  }
  EXPECT_NEAR(report.details["cost"].get<double>(), reference.details["cost"].get<double>(),
              1e-10 * reference.details["cost"].get<double>());
}

}  // namespace
}  // namespace kincal::testing
