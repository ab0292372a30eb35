#include "robot/instrument_scoring.h"

#include <cmath>
#include <stdexcept>

namespace kincal {

Dataset DistancesFromPoints(const Dataset& points, const std::vector<Eigen::Vector3d>& pivots,
                            const std::vector<std::string>& names) {
  if (pivots.empty() || pivots.size() != names.size()) {
    throw std::invalid_argument("distances from points: expected one name per pivot, one pivot at least");
  }
  points.RequireFullPoints("turning points into distances");
  Dataset out = points;
  for (size_t i = 0; i < out.rows.size(); ++i) {
    Measurement& m = out.rows[i];
    const size_t k = i % pivots.size();
    m.kind = MeasurementKind::kDistance;
    m.distance = (m.p - pivots[k]).norm();
    m.fixture = names[k];
    m.p.setZero();
    m.orientation.reset();
  }
  return out;
}

ErrorStats PairwiseDistanceErrors(const Robot& controller, const Robot& model, const Dataset& points) {
  points.RequireFullPoints("distances between points");
  const std::vector<Eigen::Vector3d> predicted = PredictMarkers(controller, model, points);
  std::vector<double> errors;
  errors.reserve(points.rows.size() * (points.rows.size() - (points.rows.empty() ? 0 : 1)) / 2);
  for (size_t i = 0; i < points.rows.size(); ++i) {
    for (size_t j = i + 1; j < points.rows.size(); ++j) {
      const double measured = (points.rows[i].p - points.rows[j].p).norm();
      errors.push_back(std::abs((predicted[i] - predicted[j]).norm() - measured));
    }
  }
  return Summarize(std::move(errors));
}

}  // namespace kincal
