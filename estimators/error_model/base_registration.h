#pragma once
// Rigid registration of point pairs in closed form, the last step of placing a start's measurement frame
// (start_placement.h).
#include <Eigen/Geometry>

namespace kincal {

// Accumulates point pairs (a_i, b_i) and returns the rigid T minimising sum |T a_i - b_i|^2: the SVD
// of the cross-covariance (Kabsch 1976; Horn, JOSA A 4(4), 1987, closed form), with Umeyama's (1991)
// sign correction so that T is a rotation, never a reflection. Streams: memory does not grow with the
// number of pairs; coordinates are shifted by the first pair so that far-away frames lose no digits.
class PointRegistration {
 public:
  void Add(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
  int count() const { return count_; }
  // False (T untouched) when fewer than three pairs or the a_i are collinear: no unique rotation.
  bool Solve(Eigen::Isometry3d* T_b_a) const;

 private:
  int count_ = 0;
  Eigen::Vector3d a0_ = Eigen::Vector3d::Zero(), b0_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_a_ = Eigen::Vector3d::Zero(), sum_b_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_ab_ = Eigen::Matrix3d::Zero(), sum_aa_ = Eigen::Matrix3d::Zero();
};

}  // namespace kincal
