// The step of the iterative compensators: plain Gauss-Newton when well conditioned, the pseudo-inverse
// or a trust-region-damped step near singular configurations, and the cheap conditioning bound.
#include <gtest/gtest.h>

#include <Eigen/QR>

#include "compensators/common/gauss_newton.h"
#include "framework/random.h"
#include "framework/svd.h"

namespace kincal {
namespace {

// A rows x cols matrix with the given singular values and random singular vectors.
Eigen::MatrixXd WithSingularValues(int rows, int cols, const Eigen::VectorXd& sigma, uint64_t seed) {
  Rng rng(seed);
  const auto random = [&](int r, int c) {
    Eigen::MatrixXd M(r, c);
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < c; ++j) M(i, j) = rng.Normal();
    return M;
  };
  const Eigen::MatrixXd U = Eigen::HouseholderQR<Eigen::MatrixXd>(random(rows, rows)).householderQ();
  const Eigen::MatrixXd V = Eigen::HouseholderQR<Eigen::MatrixXd>(random(cols, cols)).householderQ();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(rows, cols);
  for (int i = 0; i < sigma.size(); ++i) S(i, i) = sigma[i];
  return U * S * V.transpose();
}

Eigen::VectorXd PseudoInverseStep(const Eigen::MatrixXd& A, const Eigen::VectorXd& r) {
  return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(r);
}

TEST(DampedLeastSquares, WellConditionedTallIsTheLeastSquaresStep) {
  Eigen::VectorXd sigma(6);
  sigma << 2.0, 1.5, 1.0, 0.7, 0.4, 0.2;
  const Eigen::MatrixXd A = WithSingularValues(12, 6, sigma, 1);
  Rng rng(2);
  Eigen::VectorXd r(12);
  for (int i = 0; i < 12; ++i) r[i] = 0.01 * rng.Normal();
  GaussNewtonOptions o;
  o.trust_radius = 10.0;
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  const DampedLeastSquares::Step step = solver.Solve(A, r, o, &dq);
  EXPECT_FALSE(step.near_singular);
  EXPECT_FALSE(step.damped);
  EXPECT_LE((dq - PseudoInverseStep(A, r)).norm(), 1e-13 * dq.norm());
  // The conditioning bound: a lower bound of sigma_min / sigma_max, within a factor k = 6.
  const double exact = sigma.minCoeff() / sigma.maxCoeff();
  EXPECT_LE(step.sigma_ratio, exact * (1 + 1e-12));
  EXPECT_GE(step.sigma_ratio, exact / 6);
}

TEST(DampedLeastSquares, WideIsTheMinimumNormStep) {
  Eigen::VectorXd sigma(3);
  sigma << 1.0, 0.5, 0.3;
  const Eigen::MatrixXd A = WithSingularValues(3, 6, sigma, 3);
  const Eigen::VectorXd r = Eigen::Vector3d(0.01, -0.02, 0.005);
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  solver.Solve(A, r, GaussNewtonOptions(), &dq);
  EXPECT_LE((dq - PseudoInverseStep(A, r)).norm(), 1e-13 * dq.norm());
  EXPECT_LE((A * dq - r).norm(), 1e-14);
}

TEST(DampedLeastSquares, NearSingularShortStepIsNotDamped) {
  Eigen::VectorXd sigma(6);
  sigma << 1.0, 0.8, 0.6, 0.4, 0.2, 1e-5;
  const Eigen::MatrixXd A = WithSingularValues(12, 6, sigma, 4);
  const Eigen::VectorXd r = A * (Eigen::VectorXd(6) << 1e-3, 0, 0, 0, 0, 1e-3).finished();  // reachable, short
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  const DampedLeastSquares::Step step = solver.Solve(A, r, GaussNewtonOptions(), &dq);
  EXPECT_TRUE(step.near_singular);
  EXPECT_FALSE(step.damped);
  EXPECT_NEAR(step.sigma_ratio, 1e-5, 1e-9);
  EXPECT_LE((A * dq - r).norm(), 1e-12);
}

TEST(DampedLeastSquares, NearSingularLongStepIsDampedToTheTrustRadius) {
  Eigen::VectorXd sigma(6);
  sigma << 1.0, 0.8, 0.6, 0.4, 0.2, 1e-6;
  const Eigen::MatrixXd A = WithSingularValues(12, 6, sigma, 5);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullU);
  const Eigen::VectorXd r = 0.01 * svd.matrixU().col(5) + 0.01 * svd.matrixU().col(0);
  GaussNewtonOptions o;
  o.trust_radius = 0.1;
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  const DampedLeastSquares::Step step = solver.Solve(A, r, o, &dq);
  EXPECT_TRUE(step.near_singular);
  EXPECT_TRUE(step.damped);
  EXPECT_GT(step.mu, 0.0);
  EXPECT_NEAR(dq.norm(), o.trust_radius, 1e-9);
  EXPECT_NEAR(step.undamped_norm, 0.01 / 1e-6, 1.0);
  // The damped step is (A^T A + mu I)^-1 A^T r, a descent direction of |r - A dq|.
  const Eigen::MatrixXd G = A.transpose() * A + step.mu * Eigen::MatrixXd::Identity(6, 6);
  EXPECT_LE((G * dq - A.transpose() * r).norm(), 1e-12);
  EXPECT_LT((r - A * dq).norm(), r.norm());
}

TEST(DampedLeastSquares, RankDeficientStaysFinite) {
  Eigen::VectorXd sigma(6);
  sigma << 1.0, 0.8, 0.6, 0.4, 0.0, 0.0;
  const Eigen::MatrixXd A = WithSingularValues(6, 6, sigma, 6);
  Eigen::VectorXd r(6);
  r << 0.1, -0.2, 0.3, 0.0, 0.05, -0.1;
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  const DampedLeastSquares::Step step = solver.Solve(A, r, GaussNewtonOptions(), &dq);
  EXPECT_TRUE(step.near_singular);
  EXPECT_TRUE(dq.allFinite());
  EXPECT_LE(dq.norm(), GaussNewtonOptions().trust_radius * (1 + 1e-9));
  // No motion along the null space.
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  EXPECT_LE(std::abs(svd.matrixV().col(4).dot(dq)) + std::abs(svd.matrixV().col(5).dot(dq)), 1e-12);
}

TEST(DampedLeastSquares, PlainIsThePseudoInverse) {
  Eigen::VectorXd sigma(6);
  sigma << 1.0, 0.8, 0.6, 0.4, 0.2, 1e-9;
  const Eigen::MatrixXd A = WithSingularValues(12, 6, sigma, 7);
  Eigen::VectorXd r = Eigen::VectorXd::Constant(12, 0.01);
  GaussNewtonOptions o;
  o.singular_ratio = 0;
  DampedLeastSquares solver;
  Eigen::VectorXd dq;
  solver.Solve(A, r, o, &dq);
  EXPECT_LE((dq - PseudoInverseStep(A, r)).norm(), 1e-12 * dq.norm());
}

TEST(GaussNewtonOptions, Validation) {
  std::string why;
  EXPECT_TRUE(GaussNewtonOptions().IsValid(&why));
  GaussNewtonOptions o;
  o.position_tolerance = 0;
  EXPECT_FALSE(o.IsValid(&why));
  o = GaussNewtonOptions();
  o.singular_ratio = 1.0;
  EXPECT_FALSE(o.IsValid(&why));
  o = GaussNewtonOptions();
  o.trust_radius = -1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("trust_radius"), std::string::npos);
}

}  // namespace
}  // namespace kincal
