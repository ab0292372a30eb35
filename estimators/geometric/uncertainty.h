#pragma once
// Standard deviations of quantities computed from arc fits, by two routes:
//
// propagation (default): linear propagation of isotropic measurement noise. Each stop's three
//   coordinates are taken as independent with one standard deviation sigma, estimated from every fitted
//   sweep's residuals (distance from the plane, from the circle, and along it from the angle
//   regression): sigma^2 = sum of squared residuals / sum (3 stops - 8). The Jacobian of the result
//   with respect to every coordinate is taken by central differences of the whole computation (refit of
//   the perturbed sweep, then `solve`), so every step, nonlinear ones included, is in it; the covariance
//   is sigma^2 J J^T. Validated against Monte Carlo spreads in tests/estimators/geometric.
// bootstrap: the stops of every sweep are resampled with replacement, everything refitted and solved
//   again; the standard deviation over the replicates. Makes no noise model and matches the Monte Carlo
//   spread on average too, but scatters more from run to run (on the seed's arcs 0.7 to 1.8 times the
//   propagated value: a few extreme stops carry a short arc's curvature, and resampling them is
//   volatile), so it is not the default.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "estimators/geometric/arc_fit.h"
#include "estimators/geometric/sweeps.h"
#include "framework/options.h"

namespace kincal::geometric {

// Maps one arc fit per joint (index joint - 1; unswept joints hold a default ArcFit) to the quantities.
using ArcSolveFunction = std::function<Eigen::VectorXd(const std::vector<ArcFit>& fits)>;

// The keys that choose the route, for every estimator that fits arcs (geometric, ratio_regression): their
// Options derive from it.
struct UncertaintyOptions {
  // "propagation" (default; validated against Monte Carlo spreads), "bootstrap" (over the stops) or "none".
  std::string stddev = "propagation";
  int bootstrap_samples = 200;
  int bootstrap_seed = 1;
  static const OptionTable<UncertaintyOptions>& Table();
};

struct Uncertainty {
  std::string method;          // "propagation", "bootstrap" or "none"
  Eigen::VectorXd stddev;      // one per quantity; NaN when it cannot be given
  double sigma = NAN;          // propagation: the estimated noise per coordinate, m
  int degrees_of_freedom = 0;  // propagation: of sigma
  int replicates = 0;          // bootstrap: replicates that could be fitted
  std::string note;            // why stddev is NaN, if it is
  // The report's "stddev" details: method, sigma_m (null when not finite), degrees_of_freedom, replicates,
  // note.
  nlohmann::json ToJson() const;
};

// `joints`: the swept joints to take into account (1-based); `fits`: their fits at the data; `is_angle`:
// quantities whose differences wrap at 2 pi.
Uncertainty PropagateStopNoise(const SweepSet& sweeps, const std::vector<int>& joints, const ArcFitOptions& options,
                               const std::vector<ArcFit>& fits, const std::vector<bool>& is_angle,
                               const ArcSolveFunction& solve);
Uncertainty BootstrapStops(const SweepSet& sweeps, const std::vector<int>& joints, const ArcFitOptions& options,
                           const std::vector<ArcFit>& fits, const std::vector<bool>& is_angle,
                           const ArcSolveFunction& solve, int samples, uint64_t seed);
// The one `method` names ("propagation", "bootstrap", or "none": NaN for each of is_angle's quantities),
// as the options of geometric and ratio_regression choose it.
Uncertainty StopUncertainty(const std::string& method, const SweepSet& sweeps, const std::vector<int>& joints,
                            const ArcFitOptions& options, const std::vector<ArcFit>& fits,
                            const std::vector<bool>& is_angle, const ArcSolveFunction& solve, int samples,
                            uint64_t seed);

}  // namespace kincal::geometric
