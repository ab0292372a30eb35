#include "robot/fixture_fits.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/SVD>

#include "framework/error.h"
#include "robot/prediction.h"

namespace kincal {
namespace {

double SphereCost(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& distances,
                  const Eigen::Vector3d& c) {
  double cost = 0.0;
  for (size_t i = 0; i < points.size(); ++i) cost += std::pow((points[i] - c).norm() - distances[i], 2);
  return cost;
}

// Gauss-Newton with step halving: never ends worse than it started.
Eigen::Vector3d RefineSphereCentre(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& distances,
                                   Eigen::Vector3d c) {
  double cost = SphereCost(points, distances, c);
  for (int iteration = 0; iteration < 50; ++iteration) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d v = c - points[i];
      const double norm = v.norm();
      if (norm == 0.0) continue;
      const Eigen::Vector3d J = v / norm;
      JtJ += J * J.transpose();
      Jtr += J * (norm - distances[i]);
    }
    const Eigen::Vector3d step = JtJ.completeOrthogonalDecomposition().solve(-Jtr);
    double scale = 1.0;
    bool improved = false;
    for (int k = 0; k < 30 && !improved; ++k, scale *= 0.5) {
      const Eigen::Vector3d trial = c + scale * step;
      const double trial_cost = SphereCost(points, distances, trial);
      if (trial_cost < cost) {
        improved = true;
        const double gain = cost - trial_cost;
        c = trial;
        cost = trial_cost;
        if (gain <= 1e-15 * (1.0 + cost)) return c;
      }
    }
    if (!improved) break;
  }
  return c;
}

}  // namespace

Eigen::Vector3d FitSphereCentre(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& distances,
                                const Eigen::Vector3d* hint) {
  const size_t n = points.size();
  if (n < 4 || distances.size() != n) throw std::invalid_argument("a sphere fit needs four positions at least");
  const Eigen::Vector3d mean = Centroid(points);
  double mean_d2 = 0.0, mean_p2 = 0.0;
  for (size_t i = 0; i < n; ++i) {
    mean_d2 += distances[i] * distances[i] / n;
    mean_p2 += (points[i] - mean).squaredNorm() / n;
  }
  // Centred at the mean: 2 (p_i - m) . (c - m) = |p_i - m|^2 - mean|p - m|^2 - (d_i^2 - mean d^2).
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = points[i] - mean;
    A.row(static_cast<Eigen::Index>(i)) = 2.0 * u.transpose();
    b[static_cast<Eigen::Index>(i)] = u.squaredNorm() - mean_p2 - (distances[i] * distances[i] - mean_d2);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s[1] > 1e-9 * s[0])) throw std::invalid_argument("a sphere fit needs positions that are not on one line");
  std::vector<Eigen::Vector3d> starts;
  if (s[2] > 1e-6 * s[0]) {
    starts.push_back(mean + svd.solve(b));
  } else {
    // On one plane: the in-plane part is fixed, the height above the plane follows from the distances.
    const Eigen::Vector3d normal = svd.matrixV().col(2);
    Eigen::Vector3d in_plane = Eigen::Vector3d::Zero();
    for (int k = 0; k < 2; ++k) in_plane += svd.matrixV().col(k) * (svd.matrixU().col(k).dot(b) / s[k]);
    double h2 = 0.0;
    for (size_t i = 0; i < n; ++i) h2 += (distances[i] * distances[i] - (points[i] - mean - in_plane).squaredNorm()) / n;
    const double h = std::sqrt(std::max(h2, 0.0));
    starts = {mean + in_plane + h * normal, mean + in_plane - h * normal};
  }
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_cost = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& start : starts) {
    const Eigen::Vector3d c = RefineSphereCentre(points, distances, start);
    const double cost = SphereCost(points, distances, c);
    const bool tie = std::abs(cost - best_cost) <= 1e-12 * (1.0 + cost);
    if (tie ? (hint && (c - *hint).norm() < (best - *hint).norm()) : cost < best_cost) {
      best = c;
      best_cost = std::min(cost, best_cost);
    }
  }
  return best;
}

PlaneFit FitPlane(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) throw std::invalid_argument("a plane fit needs three positions at least");
  const Eigen::Vector3d mean = Centroid(points);
  Eigen::MatrixXd A(points.size(), 3);
  for (size_t i = 0; i < points.size(); ++i) A.row(static_cast<Eigen::Index>(i)) = (points[i] - mean).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinV);
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s[1] > 1e-9 * s[0])) throw std::invalid_argument("a plane fit needs positions that are not on one line");
  PlaneFit fit;
  fit.normal = svd.matrixV().col(2).normalized();
  fit.offset = fit.normal.dot(mean);
  Eigen::Index largest = 0;
  fit.normal.cwiseAbs().maxCoeff(&largest);
  if (fit.offset < 0.0 || (fit.offset == 0.0 && fit.normal[largest] < 0.0)) {
    fit.normal = -fit.normal;
    fit.offset = -fit.offset;
  }
  return fit;
}

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw std::invalid_argument("a centroid needs one position at least");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

Fixtures StartFixtures(const Robot& controller, const Robot& start, const Dataset& data) {
  Fixtures out = start.fixtures;
  const std::vector<Eigen::Vector3d> predicted = PredictMarkers(controller, start, data);
  for (MeasurementKind kind : {MeasurementKind::kDistance, MeasurementKind::kPlane, MeasurementKind::kFixedPoint}) {
    const Fixture::Type type = FixtureTypeOf(kind);
    for (const std::string& name : data.FixtureNames(kind)) {
      if (out.Find(type, name)) continue;
      std::vector<Eigen::Vector3d> points;
      std::vector<double> distances;
      int line = 0;
      for (size_t i = 0; i < data.rows.size(); ++i) {
        const Measurement& m = data.rows[i];
        if (m.kind != kind || m.fixture != name) continue;
        if (line == 0) line = m.line;
        // Fixtures live in the frame of session 0.
        points.push_back(m.session == 0 ? predicted[i]
                                        : Eigen::Vector3d(start.SessionBase(0) *
                                                          (start.SessionBase(m.session).inverse() * predicted[i])));
        distances.push_back(m.distance);
      }
      Fixture f;
      f.type = type;
      f.name = name;
      try {
        if (kind == MeasurementKind::kDistance) {
          f.position = FitSphereCentre(points, distances);
        } else if (kind == MeasurementKind::kPlane) {
          const PlaneFit plane = FitPlane(points);
          f.normal = plane.normal;
          f.offset = plane.offset;
        } else {
          f.position = Centroid(points);
        }
      } catch (const std::invalid_argument& e) {
        ThrowInputError(data.source, line, 0, FixtureTypeName(type) + " '" + name + "': " + e.what());
      }
      out.items.push_back(f);
    }
  }
  return out;
}

}  // namespace kincal
