#include "estimators/error_model/base_registration.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace kincal {

void PointRegistration::Add(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (count_ == 0) {
    a0_ = a;
    b0_ = b;
  }
  const Eigen::Vector3d da = a - a0_, db = b - b0_;
  sum_a_ += da;
  sum_b_ += db;
  sum_ab_ += da * db.transpose();
  sum_aa_ += da * da.transpose();
  ++count_;
}

bool PointRegistration::Solve(Eigen::Isometry3d* T_b_a) const {
  if (count_ < 3) return false;
  const double n = count_;
  const Eigen::Vector3d mean_a = sum_a_ / n, mean_b = sum_b_ / n;
  const Eigen::Matrix3d H = sum_ab_ - n * mean_a * mean_b.transpose();  // sum (a - a_bar)(b - b_bar)^T
  const Eigen::Matrix3d C = sum_aa_ - n * mean_a * mean_a.transpose();
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues();
  if (!(spread[1] > 1e-12 * spread[2])) return false;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixV() * S * svd.matrixU().transpose();
  T_b_a->setIdentity();
  T_b_a->linear() = R;
  T_b_a->translation() = (b0_ + mean_b) - R * (a0_ + mean_a);
  return true;
}

}  // namespace kincal
