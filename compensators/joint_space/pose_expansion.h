#pragma once
// PoseExpansion: a pose [R | p] (3 x 4, SI) as a tensor-product series in some joints, fitted offline
// by linear least squares on a tensor grid of samples.
//
// Basis per joint, of degree d: a revolute joint q uses the Fourier terms 1, cos(k q), sin(k q),
// k = 1..d (2 d + 1 terms, valid for every angle: the series is periodic); a prismatic joint uses the
// Chebyshev polynomials T_0..T_d of x = (2 q - low - high) / (high - low) (d + 1 terms, fitted over
// [low, high] only: outside it a lookup reports `inside = false`).
//
// Why degree 1 is exact for a rigid serial chain: every joint moves its link by a one-parameter motion,
// a rotation Rot(axis, q) = I + sin q [a]x + (1 - cos q) [a]x^2 or a translation along a fixed axis, so
// each entry of T = ... L_i Motion_i(q_i) L_(i+1) ... is multilinear in (cos q_i, sin q_i) (or in q_i):
// a series of degree 1 in each joint, with 3^k terms for k revolute joints (Murray, Li and Sastry 1994,
// product-of-exponentials formula, eq. 3.3). Higher degrees are for models that are not rigid chains.
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/kinematic_model.h"

namespace kincal {

class PoseExpansion {
 public:
  using Pose34 = Eigen::Matrix<double, 3, 4>;
  struct Axis {
    int joint = 0;  // 0-based index into the full joint vector
    JointType type = JointType::kRevolute;
    double low = 0.0, high = 0.0;  // m: the fitted range of a prismatic joint (unused for revolute)
  };

  PoseExpansion() = default;
  // Fits f, called with full joint vectors equal to `rest` except on the axes' joints. No axes: the
  // constant f(rest). Throws std::invalid_argument for a degree outside 1..8, more than 16 axes, a prismatic axis with
  // an empty range or a joint listed twice.
  static PoseExpansion Fit(std::vector<Axis> axes, int degree, const Eigen::VectorXd& rest,
                           const std::function<Eigen::Isometry3d(const Eigen::VectorXd&)>& f);

  const std::vector<Axis>& axes() const { return axes_; }
  int num_terms() const { return static_cast<int>(coefficients_.cols()); }
  // Term t of the series as a 3 x 4 pose (its coefficients): with one revolute axis of degree 1 the pose
  // is Term(0) + cos(q) Term(1) + sin(q) Term(2), which callers on a fast path evaluate inline.
  Pose34 Term(int t) const { return Eigen::Map<const Pose34>(coefficients_.col(t).data()); }
  size_t memory_bytes() const { return coefficients_.size() * sizeof(double); }

  // The pose at the full joint vector q and, when dT_dq is not null, its derivative along each axis
  // (dT_dq[a] for axes()[a]). Returns false when a prismatic joint lies outside its fitted range (the
  // series is still evaluated there).
  bool Evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Pose34* T, Pose34* dT_dq = nullptr) const;
  // The same for an expansion in one joint, at that joint's value x: the fast path of a lookup.
  bool EvaluateSingle(double x, Pose34* T, Pose34* dT_dx = nullptr) const;

 private:
  int TermsOf(const Axis& axis) const;
  // Basis values (and derivatives d/dq) of one axis at q into value[0..TermsOf), derivative[...].
  void Basis(const Axis& axis, double q, double* value, double* derivative) const;

  std::vector<Axis> axes_;
  int degree_ = 1;
  // 12 x terms: column t holds the 12 entries of [R | p] (column-major) multiplying the t-th product of
  // basis functions; the first axis varies fastest.
  Eigen::Matrix<double, 12, Eigen::Dynamic> coefficients_;
};

}  // namespace kincal
