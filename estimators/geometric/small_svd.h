#pragma once
// The singular values and right singular vectors of an m x N matrix (N = 3 or 4, m any) as Eigen's
// JacobiSVD computes them for a tall matrix: its column-pivoting QR preconditioner, then two-sided Jacobi
// on the N x N triangle. Z P = Q R and R = U S V_R^T give Z = (Q U) S (P V_R)^T. Written out because
// JacobiSVD of a dynamic-row matrix also instantiates the preconditioner of the wide case and both
// Householder sequences: about half the compile time of the files that used it (circle_fit.cc 40 s of
// CPU at -O3, 19 s this way), for the same arithmetic.
#include <limits>

#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/SVD>

namespace kincal::geometric {

template <int N>
struct SmallSvd {
  Eigen::Matrix<double, N, 1> singular_values;  // descending
  Eigen::Matrix<double, N, N> V;                // right singular vectors, by column
};

template <int N>
SmallSvd<N> RightSingularVectors(const Eigen::Matrix<double, Eigen::Dynamic, N>& Z) {
  using Tall = Eigen::Matrix<double, Eigen::Dynamic, N>;
  // Fewer rows than columns: zero rows appended change neither V nor the nonzero singular values; the
  // missing ones are 0, as JacobiSVD's full V reports them.
  Tall padded;
  const Tall* A = &Z;
  if (Z.rows() < N) {
    padded = Tall::Zero(N, N);
    padded.topRows(Z.rows()) = Z;
    A = &padded;
  }
  const Eigen::ColPivHouseholderQR<Tall> qr(*A);
  const Eigen::Matrix<double, N, N> R = qr.matrixQR().template topRows<N>().template triangularView<Eigen::Upper>();
  const Eigen::JacobiSVD<Eigen::Matrix<double, N, N>> svd(R, Eigen::ComputeFullV);
  SmallSvd<N> out;
  if (svd.info() != Eigen::Success) {
    // A non-finite entry: JacobiSVD leaves its results unset; NaN makes the callers' finiteness checks fail.
    out.singular_values.setConstant(std::numeric_limits<double>::quiet_NaN());
    out.V.setConstant(std::numeric_limits<double>::quiet_NaN());
    return out;
  }
  out.singular_values = svd.singularValues();
  out.V = qr.colsPermutation() * svd.matrixV();
  return out;
}

}  // namespace kincal::geometric
