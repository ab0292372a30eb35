#pragma once
// The one place the error model inverts its information matrix J^T W J (plus the priors' diagonal): the
// parameter covariance of a fit (prediction_uncertainty.h), selection's Gauss-Newton steps and fold
// covariances (select_error_model.cc). A pseudo-inverse in the column-normalised basis, eigenvalues below
// 1e-12 of the largest left out: a fit can end with combinations the data hardly determine (condition
// numbers of 1e8 and more on the UR10), where a Cholesky factorisation fails, yet they barely move the
// training poses' predictions. Units: the inverse of A's (x's units squared per m^2 for J^T J).
#include <vector>

#include <Eigen/Core>

namespace kincal {

// A^+ as above for a symmetric positive semi-definite A; all NaN when A has a non-finite entry or the
// eigensolver fails.
Eigen::MatrixXd ScaledPseudoInverse(const Eigen::MatrixXd& A);
// The same of A's principal submatrix on `columns` (q x q, in the order of `columns`).
Eigen::MatrixXd ScaledPseudoInverse(const Eigen::MatrixXd& A, const std::vector<int>& columns);

}  // namespace kincal
