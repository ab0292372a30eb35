#include "estimators/geometric/circle_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "estimators/geometric/small_svd.h"

namespace kincal::geometric {
namespace {

// Points centred on their centroid and divided by their RMS distance from it.
struct Normalized {
  std::vector<Eigen::Vector2d> p;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double scale = 1.0;
};

Normalized Normalize(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 3) {
    throw std::invalid_argument("circle fit needs at least 3 points, got " + std::to_string(points.size()));
  }
  Normalized n;
  for (const auto& p : points) n.centroid += p;
  n.centroid /= static_cast<double>(points.size());
  double sum2 = 0.0;
  for (const auto& p : points) sum2 += (p - n.centroid).squaredNorm();
  n.scale = std::sqrt(sum2 / static_cast<double>(points.size()));
  if (!(n.scale > 0.0)) throw std::invalid_argument("circle fit: the points coincide");
  for (const auto& p : points) n.p.push_back((p - n.centroid) / n.scale);
  return n;
}

CircleFit2d Denormalize(const Normalized& n, const Eigen::Vector2d& center, double radius) {
  if (!center.allFinite() || !std::isfinite(radius) || !(radius > 0.0)) {
    throw std::invalid_argument("circle fit: the points lie on a straight line (no finite circle)");
  }
  CircleFit2d fit;
  fit.center = n.centroid + n.scale * center;
  fit.radius = n.scale * radius;
  return fit;
}

// Circle A (x^2 + y^2) + B x + C y + D = 0 -> centre and radius.
CircleFit2d FromAlgebraic(const Normalized& n, const Eigen::Vector4d& A) {
  const Eigen::Vector2d center(-A[1] / (2 * A[0]), -A[2] / (2 * A[0]));
  const double radius = std::sqrt(A[1] * A[1] + A[2] * A[2] - 4 * A[0] * A[3]) / (2 * std::abs(A[0]));
  return Denormalize(n, center, radius);
}

}  // namespace

std::string ToString(CircleFitMethod method) {
  switch (method) {
    case CircleFitMethod::kKasa:
      return "kasa";
    case CircleFitMethod::kPratt:
      return "pratt";
    case CircleFitMethod::kTaubin:
      return "taubin";
    case CircleFitMethod::kGeometric:
      return "geometric";
  }
  return "unknown";
}

std::vector<std::string> CircleFitMethodNames() { return {"kasa", "pratt", "taubin", "geometric"}; }

CircleFitMethod ParseCircleFitMethod(const std::string& name) {
  for (auto m :
       {CircleFitMethod::kKasa, CircleFitMethod::kPratt, CircleFitMethod::kTaubin, CircleFitMethod::kGeometric}) {
    if (ToString(m) == name) return m;
  }
  throw std::invalid_argument("unknown circle fit '" + name + "' (expected kasa, pratt, taubin or geometric)");
}

CircleFit2d FitCircleKasa(const std::vector<Eigen::Vector2d>& points) {
  const Normalized n = Normalize(points);
  const int m = static_cast<int>(n.p.size());
  Eigen::MatrixX3d M(m, 3);
  Eigen::VectorXd b(m);
  for (int k = 0; k < m; ++k) {
    M.row(k) << n.p[k].x(), n.p[k].y(), 1.0;
    b[k] = -n.p[k].squaredNorm();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixX3d> qr(M);
  if (qr.rank() < 3) throw std::invalid_argument("circle fit: the points lie on a straight line (no finite circle)");
  const Eigen::Vector3d s = qr.solve(b);  // x^2 + y^2 + D x + E y + F = 0
  return FromAlgebraic(n, Eigen::Vector4d(1.0, s[0], s[1], s[2]));
}

CircleFit2d FitCircleTaubin(const std::vector<Eigen::Vector2d>& points) {
  // Chernov, "Circular and linear regression" (2010), TaubinSVD: with centred data the constraint
  // 4 mean(z) A^2 + B^2 + C^2 = 1 becomes a unit-norm constraint after scaling the z column.
  const Normalized n = Normalize(points);
  const int m = static_cast<int>(n.p.size());
  double z_mean = 0.0;
  for (const auto& p : n.p) z_mean += p.squaredNorm();
  z_mean /= m;  // 1 by the normalisation, kept general for clarity
  const double root = 2.0 * std::sqrt(z_mean);
  Eigen::MatrixX3d Z(m, 3);
  for (int k = 0; k < m; ++k) Z.row(k) << (n.p[k].squaredNorm() - z_mean) / root, n.p[k].x(), n.p[k].y();
  const Eigen::Vector3d v = RightSingularVectors<3>(Z).V.col(2);
  const double A = v[0] / root;
  return FromAlgebraic(n, Eigen::Vector4d(A, v[1], v[2], -z_mean * A));
}

CircleFit2d FitCirclePratt(const std::vector<Eigen::Vector2d>& points) {
  // Chernov (2010), PrattSVD: minimise |Z A|^2 subject to A^T B A = 1, B the Pratt constraint matrix.
  // With Z = U S V^T and Y = S V^T A this is the eigenproblem of W^T B^-1 W (W = V S); the answer is the
  // eigenvector of the smallest positive eigenvalue, mapped back by A = V S^-1 Y.
  const Normalized n = Normalize(points);
  const int m = static_cast<int>(n.p.size());
  Eigen::MatrixX4d Z(m, 4);
  for (int k = 0; k < m; ++k) Z.row(k) << n.p[k].squaredNorm(), n.p[k].x(), n.p[k].y(), 1.0;
  const SmallSvd<4> svd = RightSingularVectors<4>(Z);
  const Eigen::Vector4d s = svd.singular_values;
  const Eigen::Matrix4d V = svd.V;
  Eigen::Vector4d A;
  if (s[3] < 1e-12 * s[0]) {
    A = V.col(3);  // the points are exactly on a circle (or line): the null vector
  } else {
    Eigen::Matrix4d B_inv = Eigen::Matrix4d::Zero();
    B_inv(0, 3) = B_inv(3, 0) = -0.5;
    B_inv(1, 1) = B_inv(2, 2) = 1.0;
    const Eigen::Matrix4d W = V * s.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(W.transpose() * B_inv * W);
    // Eigenvalues ascending: one negative (B is indefinite), then the smallest positive.
    const Eigen::Vector4d Y = eig.eigenvectors().col(1);
    A = V * s.cwiseInverse().asDiagonal() * Y;
  }
  return FromAlgebraic(n, A);
}

CircleFit2d FitCircleGeometric(const std::vector<Eigen::Vector2d>& points, const CircleFit2d& initial,
                               int max_iterations) {
  const Normalized n = Normalize(points);
  const int m = static_cast<int>(n.p.size());
  Eigen::Vector3d x((initial.center.x() - n.centroid.x()) / n.scale, (initial.center.y() - n.centroid.y()) / n.scale,
                    initial.radius / n.scale);
  const auto residuals = [&](const Eigen::Vector3d& c, Eigen::VectorXd* r, Eigen::MatrixX3d* J) {
    r->resize(m);
    if (J) J->resize(m, 3);
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector2d d = n.p[k] - c.head<2>();
      const double dist = d.norm();
      (*r)[k] = dist - c[2];
      if (J) {
        // A point at the centre has no defined direction; any unit vector gives a valid subgradient.
        const Eigen::Vector2d u = dist > 0.0 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1.0, 0.0);
        J->row(k) << -u.x(), -u.y(), -1.0;
      }
    }
  };
  Eigen::VectorXd r, r_new;
  Eigen::MatrixX3d J;
  residuals(x, &r, &J);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  CircleFit2d fit;
  fit.converged = false;
  int it = 0;
  for (; it < max_iterations; ++it) {
    const Eigen::Matrix3d JtJ = J.transpose() * J;
    const Eigen::Vector3d g = J.transpose() * r;
    bool accepted = false;
    bool tiny_step = false;
    while (!accepted && lambda < 1e12) {
      Eigen::Matrix3d H = JtJ;
      H.diagonal() += lambda * JtJ.diagonal();
      const Eigen::Vector3d step = -H.ldlt().solve(g);
      tiny_step = step.norm() <= 1e-15 * (1.0 + x.norm());
      const Eigen::Vector3d x_new = x + step;
      residuals(x_new, &r_new, nullptr);
      const double cost_new = r_new.squaredNorm();
      if (cost_new <= cost) {
        x = x_new;
        cost = cost_new;
        residuals(x, &r, &J);
        lambda = std::max(lambda / 10.0, 1e-12);
        accepted = true;
      } else {
        lambda *= 10.0;
      }
      if (tiny_step) break;
    }
    // Converged: the step is at rounding level, or no step lowers the cost any more.
    if (tiny_step || !accepted) {
      fit.converged = true;
      break;
    }
  }
  fit.iterations = it;
  const CircleFit2d out = Denormalize(n, x.head<2>(), std::abs(x[2]));
  fit.center = out.center;
  fit.radius = out.radius;
  return fit;
}

CircleFit2d FitCircle(const std::vector<Eigen::Vector2d>& points, CircleFitMethod method, int max_iterations) {
  switch (method) {
    case CircleFitMethod::kKasa:
      return FitCircleKasa(points);
    case CircleFitMethod::kPratt:
      return FitCirclePratt(points);
    case CircleFitMethod::kTaubin:
      return FitCircleTaubin(points);
    case CircleFitMethod::kGeometric:
      return FitCircleGeometric(points, FitCircleTaubin(points), max_iterations);
  }
  throw std::invalid_argument("unknown circle fit method");
}

}  // namespace kincal::geometric
