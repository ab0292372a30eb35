#include "estimators/error_model/covariance.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace kincal {

Eigen::MatrixXd ScaledPseudoInverse(const Eigen::MatrixXd& A) {
  const Eigen::Index p = A.rows();
  // Non-finite entries (a fit driven to huge values) would send the eigensolver astray.
  if (!A.allFinite()) return Eigen::MatrixXd::Constant(p, p, NAN);
  Eigen::VectorXd d(p);
  for (Eigen::Index j = 0; j < p; ++j) d[j] = A(j, j) > 0.0 ? 1.0 / std::sqrt(A(j, j)) : 0.0;
  const Eigen::MatrixXd S = d.asDiagonal() * A * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) return Eigen::MatrixXd::Constant(p, p, NAN);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double cut = 1e-12 * std::max(lambda.maxCoeff(), 0.0);
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(p);
  for (Eigen::Index j = 0; j < p; ++j)
    if (lambda[j] > cut && lambda[j] > 0.0) inv[j] = 1.0 / lambda[j];
  return d.asDiagonal() * (eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose()) * d.asDiagonal();
}

Eigen::MatrixXd ScaledPseudoInverse(const Eigen::MatrixXd& A, const std::vector<int>& columns) {
  const int q = static_cast<int>(columns.size());
  Eigen::MatrixXd M(q, q);
  for (int a = 0; a < q; ++a)
    for (int c = 0; c < q; ++c) M(a, c) = A(columns[a], columns[c]);
  return ScaledPseudoInverse(M);
}

}  // namespace kincal
