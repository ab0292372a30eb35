#pragma once
// One damped least-squares step of a small system, the kernel of the Gauss-Newton and
// Levenberg-Marquardt loops on joint angles (robot/inverse_kinematics.cc, the nominal inverse
// kinematics' polish, compensators/common/gauss_newton.cc): for a residual that moves as
// r(x + dx) ~ r - J dx, the step
//     dx = argmin |r - J dx|^2 + mu dx^T D dx,   i.e.   (J^T J + mu D) dx = J^T r,
// with the damping rule D a parameter: the identity (Levenberg) or diag(J^T J) (Marquardt, invariant
// to the scaling of the unknowns).
//
// The systems are 3 to 7 unknowns: plain loops replace Eigen's blocked dynamic-size kernels, whose
// set-up costs more than the arithmetic at these sizes. Size fixes the number of unknowns at compile
// time (6 for a 6-joint arm: no heap allocation, loops unrolled, values kept in registers); Size =
// Eigen::Dynamic takes any number up to MaxSize (no heap allocation) or any at all (MaxSize = Dynamic).
#include <cmath>

#include <Eigen/Core>

namespace kincal {

enum class Damping {
  kIdentity,   // D = I
  kMarquardt,  // D = diag(J^T J)
};

template <int Size, int MaxSize = Size>
class DampedNormalEquations {
 public:
  using Matrix = Eigen::Matrix<double, Size, Size, Eigen::ColMajor, MaxSize, MaxSize>;
  using Vector = Eigen::Matrix<double, Size, 1, Eigen::ColMajor, MaxSize, 1>;

  // H = J^T J and g = J^T r: the unknowns are J's columns (Size of them, or at most MaxSize).
  template <typename DerivedJ, typename DerivedR>
  void Assemble(const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedR>& r) {
    const int n = static_cast<int>(J.cols());
    H_.resize(n, n);
    g_.resize(n);
    for (int j = 0; j < n; ++j) {
      for (int i = j; i < n; ++i) H_(i, j) = H_(j, i) = J.col(i).dot(J.col(j));
      g_[j] = J.col(j).dot(r);
    }
  }

  // The dual system of a wide J (fewer rows than columns; Size or at most MaxSize rows): H = J J^T and g = r,
  // whose solution y gives the minimum-norm step dx = J^T y.
  template <typename DerivedJ, typename DerivedR>
  void AssembleWide(const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedR>& r) {
    const int m = static_cast<int>(J.rows());
    H_.resize(m, m);
    for (int j = 0; j < m; ++j) {
      for (int i = j; i < m; ++i) H_(i, j) = H_(j, i) = J.row(i).dot(J.row(j));
    }
    g_ = r;
  }

  // Cholesky factor of H + mu D (lower triangle); false unless it is numerically positive definite.
  // The reciprocals of its diagonal are kept: one division per column instead of one per entry here
  // and in the solves (the divisions' latency was most of the time of these small systems).
  bool Factor(double mu = 0.0, Damping damping = Damping::kIdentity) {
    const int k = size();
    L_ = H_;
    inverse_diagonal_.resize(k);
    if (mu != 0.0) {
      for (int i = 0; i < k; ++i) L_(i, i) += damping == Damping::kIdentity ? mu : mu * H_(i, i);
    }
    for (int j = 0; j < k; ++j) {
      double d = L_(j, j);
      for (int p = 0; p < j; ++p) d -= L_(j, p) * L_(j, p);
      if (!(d > 0)) return false;
      d = std::sqrt(d);
      L_(j, j) = d;
      const double inverse = 1.0 / d;
      inverse_diagonal_[j] = inverse;
      for (int i = j + 1; i < k; ++i) {
        double s = L_(i, j);
        for (int p = 0; p < j; ++p) s -= L_(i, p) * L_(j, p);
        L_(i, j) = s * inverse;
      }
    }
    return true;
  }

  // (H + mu D)^-1 b in place, for the last successful Factor.
  void SolveInPlace(Vector* b) const {
    Vector& y = *b;
    const int k = size();
    for (int i = 0; i < k; ++i) {
      double s = y[i];
      for (int p = 0; p < i; ++p) s -= L_(i, p) * y[p];
      y[i] = s * inverse_diagonal_[i];
    }
    for (int i = k - 1; i >= 0; --i) {
      double s = y[i];
      for (int p = i + 1; p < k; ++p) s -= L_(p, i) * y[p];
      y[i] = s * inverse_diagonal_[i];
    }
  }

  // The step (H + mu D)^-1 g (of the dual system after AssembleWide), for the last successful Factor.
  Vector Step() const {
    Vector y = g_;
    SolveInPlace(&y);
    return y;
  }

  // trace((H + mu D)^-1) = |L^-1|_F^2, column by column of L^-1 by forward substitution. With trace(H)
  // it bounds the condition: cond(H) <= trace(H) trace(H^-1) <= k^2 cond(H).
  double InverseTrace() const {
    const int k = size();
    Vector x(k);
    double sum = 0.0;
    for (int c = 0; c < k; ++c) {
      x[c] = inverse_diagonal_[c];
      sum += x[c] * x[c];
      for (int i = c + 1; i < k; ++i) {
        double s = 0.0;
        for (int p = c; p < i; ++p) s -= L_(i, p) * x[p];
        x[i] = s * inverse_diagonal_[i];
        sum += x[i] * x[i];
      }
    }
    return sum;
  }

  int size() const { return static_cast<int>(H_.rows()); }
  const Matrix& H() const { return H_; }  // J^T J (J J^T after AssembleWide), undamped
  const Vector& g() const { return g_; }  // J^T r (r after AssembleWide)

 private:
  Matrix H_, L_;
  Vector g_, inverse_diagonal_;
};

}  // namespace kincal
