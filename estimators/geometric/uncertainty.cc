#include "estimators/geometric/uncertainty.h"

#include <cmath>
#include <stdexcept>

#include "estimators/geometric/axis_fit.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal::geometric {

nlohmann::json Uncertainty::ToJson() const {
  return {{"method", method},
          {"sigma_m", std::isfinite(sigma) ? nlohmann::json(sigma) : nlohmann::json(nullptr)},
          {"degrees_of_freedom", degrees_of_freedom},
          {"replicates", replicates},
          {"note", note}};
}
namespace {

// Coordinate step of the central differences, m: far below any arc (so the linearisation holds) and far
// above rounding of coordinates of a few metres (so the difference keeps about 10 digits).
constexpr double kStep = 1e-6;

Eigen::VectorXd Difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::vector<bool>& is_angle) {
  Eigen::VectorXd d = a - b;
  for (int k = 0; k < d.size(); ++k) {
    if (k < static_cast<int>(is_angle.size()) && is_angle[k]) d[k] = WrapAngle(d[k]);
  }
  return d;
}

}  // namespace

Uncertainty PropagateStopNoise(const SweepSet& sweeps, const std::vector<int>& joints, const ArcFitOptions& options,
                               const std::vector<ArcFit>& fits, const std::vector<bool>& is_angle,
                               const ArcSolveFunction& solve) {
  Uncertainty u;
  u.method = "propagation";
  const Eigen::VectorXd value = solve(fits);
  double rss = 0.0;
  for (int j : joints) {
    rss += fits[j - 1].residual_sum_squares;
    u.degrees_of_freedom += fits[j - 1].degrees_of_freedom;
  }
  u.stddev = Eigen::VectorXd::Constant(value.size(), NAN);
  if (u.degrees_of_freedom <= 0) {
    u.note = "no residual degrees of freedom to estimate the noise (at least 3 stops per sweep beyond 8/3)";
    return u;
  }
  u.sigma = std::sqrt(rss / u.degrees_of_freedom);
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(value.size());
  std::vector<ArcFit> perturbed = fits;
  for (int j : joints) {
    const Sweep& s = sweeps.sweeps[j - 1];
    std::vector<std::vector<Eigen::Vector3d>> points = s.marker_points;
    for (auto& marker : points) {
      for (size_t k = 0; k < marker.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
          const double original = marker[k][c];
          marker[k][c] = original + kStep;
          perturbed[j - 1] = FitAxis(points, s.x, options);
          const Eigen::VectorXd plus = solve(perturbed);
          marker[k][c] = original - kStep;
          perturbed[j - 1] = FitAxis(points, s.x, options);
          const Eigen::VectorXd minus = solve(perturbed);
          marker[k][c] = original;
          variance += (Difference(plus, minus, is_angle) / (2 * kStep)).cwiseAbs2();
        }
      }
    }
    perturbed[j - 1] = fits[j - 1];
  }
  u.stddev = u.sigma * variance.cwiseSqrt();
  return u;
}

Uncertainty BootstrapStops(const SweepSet& sweeps, const std::vector<int>& joints, const ArcFitOptions& options,
                           const std::vector<ArcFit>& fits, const std::vector<bool>& is_angle,
                           const ArcSolveFunction& solve, int samples, uint64_t seed) {
  Uncertainty u;
  u.method = "bootstrap";
  const Eigen::VectorXd value = solve(fits);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(value.size()), sum2 = Eigen::VectorXd::Zero(value.size());
  Rng rng(seed);
  std::vector<ArcFit> replicate = fits;
  for (int b = 0; b < samples; ++b) {
    bool ok = true;
    for (int j : joints) {
      const Sweep& s = sweeps.sweeps[j - 1];
      const int m = static_cast<int>(s.x.size());
      // A stop is resampled with every marker measured at it.
      std::vector<std::vector<Eigen::Vector3d>> points(s.marker_points.size(), std::vector<Eigen::Vector3d>(m));
      std::vector<double> x(m);
      for (int k = 0; k < m; ++k) {
        const int pick = static_cast<int>(rng.NextU64() % static_cast<uint64_t>(m));
        for (size_t i = 0; i < points.size(); ++i) points[i][k] = s.marker_points[i][pick];
        x[k] = s.x[pick];
      }
      try {
        replicate[j - 1] = FitAxis(points, x, options);
      } catch (const std::invalid_argument&) {
        ok = false;  // e.g. all picks at one stop: this replicate cannot be fitted
        break;
      }
    }
    if (!ok) continue;
    const Eigen::VectorXd d = Difference(solve(replicate), value, is_angle);
    sum += d;
    sum2 += d.cwiseAbs2();
    ++u.replicates;
  }
  if (u.replicates < 2 || u.replicates < samples / 2) {
    u.stddev = Eigen::VectorXd::Constant(value.size(), NAN);
    u.note = "only " + std::to_string(u.replicates) + " of " + std::to_string(samples) +
             " bootstrap replicates could be fitted";
    return u;
  }
  const double r = u.replicates;
  u.stddev = ((sum2 - sum.cwiseAbs2() / r) / (r - 1)).cwiseMax(0.0).cwiseSqrt();
  return u;
}

Uncertainty StopUncertainty(const std::string& method, const SweepSet& sweeps, const std::vector<int>& joints,
                            const ArcFitOptions& options, const std::vector<ArcFit>& fits,
                            const std::vector<bool>& is_angle, const ArcSolveFunction& solve, int samples,
                            uint64_t seed) {
  if (method == "propagation") return PropagateStopNoise(sweeps, joints, options, fits, is_angle, solve);
  if (method == "bootstrap") return BootstrapStops(sweeps, joints, options, fits, is_angle, solve, samples, seed);
  Uncertainty u;
  u.method = "none";
  u.stddev = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(is_angle.size()), NAN);
  return u;
}

}  // namespace kincal::geometric
