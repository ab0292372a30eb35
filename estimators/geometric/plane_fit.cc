#include "estimators/geometric/plane_fit.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "estimators/geometric/small_svd.h"

namespace kincal::geometric {

PlaneFit FitPlane(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw std::invalid_argument("plane fit: no points");
  const int m = static_cast<int>(points.size());
  PlaneFit fit;
  for (const auto& p : points) fit.centroid += p;
  fit.centroid /= m;
  Eigen::MatrixX3d A(m, 3);
  for (int k = 0; k < m; ++k) A.row(k) = (points[k] - fit.centroid).transpose();
  // SVD of the centred points rather than an eigen-decomposition of their scatter matrix: squaring the
  // matrix would square its condition number and lose half the digits of a nearly flat arc's normal.
  const SmallSvd<3> svd = RightSingularVectors<3>(A);
  for (int i = 0; i < 3; ++i) fit.spread[i] = svd.singular_values[i] / std::sqrt(static_cast<double>(m));
  fit.e1 = svd.V.col(0);
  fit.e2 = svd.V.col(1);
  fit.normal = fit.e1.cross(fit.e2).normalized();
  return fit;
}

}  // namespace kincal::geometric
