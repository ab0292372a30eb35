// The damped least-squares kernel (framework/damped_least_squares.h) against direct solves of the same
// problems by other means: the damped problem as an augmented least-squares problem solved by
// Householder QR, the minimum-norm step by a complete orthogonal decomposition, traces by an inverse.
#include "framework/damped_least_squares.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "framework/random.h"

namespace kincal {
namespace {

Eigen::MatrixXd RandomMatrix(int rows, int cols, uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd M(rows, cols);
  for (int j = 0; j < cols; ++j) {
    // Columns of different scales, as joint Jacobians have (m / rad beside rad / rad).
    for (int i = 0; i < rows; ++i) M(i, j) = rng.Uniform(-1, 1) * (1 + 3 * j);
  }
  return M;
}

// argmin |r - J dx|^2 + mu dx^T D dx as the plain least-squares problem [J; sqrt(mu D)] dx ~ [r; 0].
Eigen::VectorXd AugmentedSolve(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, double mu, Damping damping) {
  const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(m + n, n);
  K.topRows(m) = J;
  for (int j = 0; j < n; ++j) {
    K(m + j, j) = std::sqrt(mu * (damping == Damping::kIdentity ? 1.0 : J.col(j).squaredNorm()));
  }
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m + n);
  b.head(m) = r;
  return K.householderQr().solve(b);
}

TEST(DampedNormalEquations, StepIsTheDampedLeastSquaresSolution) {
  const Eigen::MatrixXd J = RandomMatrix(9, 6, 1);
  const Eigen::VectorXd r = RandomMatrix(9, 1, 2);
  for (const Damping damping : {Damping::kIdentity, Damping::kMarquardt}) {
    for (const double mu : {0.0, 1e-3, 0.7, 40.0}) {
      const Eigen::VectorXd expected = AugmentedSolve(J, r, mu, damping);
      DampedNormalEquations<6> fixed;
      fixed.Assemble(J, r);
      ASSERT_TRUE(fixed.Factor(mu, damping));
      DampedNormalEquations<Eigen::Dynamic> dynamic;
      dynamic.Assemble(J, r);
      ASSERT_TRUE(dynamic.Factor(mu, damping));
      EXPECT_LT((Eigen::VectorXd(fixed.Step()) - expected).norm(), 1e-12 * expected.norm()) << mu;
      EXPECT_LT((dynamic.Step() - expected).norm(), 1e-12 * expected.norm()) << mu;
      // trace((J^T J + mu D)^-1) from the factor, against the inverse of the matrix.
      Eigen::MatrixXd damped = J.transpose() * J;
      const Eigen::VectorXd d = damping == Damping::kIdentity ? Eigen::VectorXd::Ones(6) : Eigen::VectorXd(damped.diagonal());
      damped.diagonal() += mu * d;
      const double trace = damped.inverse().trace();
      EXPECT_NEAR(fixed.InverseTrace(), trace, 1e-12 * trace);
    }
  }
}

TEST(DampedNormalEquations, WideSystemGivesTheMinimumNormStep) {
  const Eigen::MatrixXd J = RandomMatrix(3, 6, 3);
  const Eigen::VectorXd r = RandomMatrix(3, 1, 4);
  DampedNormalEquations<Eigen::Dynamic, 8> normal;  // fixed capacity, size at run time
  normal.AssembleWide(J, r);
  ASSERT_TRUE(normal.Factor());
  const Eigen::VectorXd dx = J.transpose() * normal.Step();
  const Eigen::VectorXd expected = J.completeOrthogonalDecomposition().solve(r);
  EXPECT_LT((dx - expected).norm(), 1e-12 * expected.norm());
  EXPECT_LT((J * dx - r).norm(), 1e-12 * r.norm());
}

TEST(DampedNormalEquations, SingularSystemIsNotFactoredUndamped) {
  Eigen::MatrixXd J = RandomMatrix(6, 4, 5);
  J.col(2) = 2.0 * J.col(0);  // rank 3
  DampedNormalEquations<Eigen::Dynamic> normal;
  normal.Assemble(J, Eigen::VectorXd::Ones(6));
  // Rank deficient: H is singular, its factor at best at rounding level; damped it is definite.
  if (normal.Factor()) {
    EXPECT_GT(normal.InverseTrace() * normal.H().trace(), 1e12);
  }
  EXPECT_TRUE(normal.Factor(1e-6));
  EXPECT_TRUE(normal.Factor(1e-6, Damping::kMarquardt));
}

}  // namespace
}  // namespace kincal
