#pragma once
// The angle of each stop about a fitted axis, from the in-plane directions of the markers (METHOD.md 3.1),
// signed and unwrapped with the joint's drive variable x (its reading, through coupling and ratios).
//
// Why the readings and not only the points: a direction in the plane gives the angle modulo 2 pi, and a
// normal fitted to points gives the axis up to its sign. Neither matters for the seed's 2 deg steps, but
// a wrist swept through 144-288 deg between stops (industrial CPA data) turns by more than pi between
// stops, and unwrapping by the shortest way then runs the angles backwards: the axis comes out reversed and
// the angle slope negative. The readings tell the turn between consecutive stops (sorted by x) to far
// better than pi, so each step is taken as dx + remainder(d_raw - dx, 2 pi), and the axis' sign is the one
// whose angles follow the readings (angle - x closest to a constant). This assumes only that the drive
// variable's scale is right to well within pi per step and that the joint turns the way its reading says,
// which is what the drive variable means.
#include <vector>

namespace kincal::geometric {

// `raw[m][k]`: marker m's in-plane angle at stop k about the unsigned normal; `x[k]`: the drive variable;
// `weights[m]`: marker m's weight (its radius squared: the angle noise of a marker near the axis is large).
// Fills `unwrapped[m][k]` with the angles about the signed axis and returns the sign (+1: the normal as
// given; -1: the axis is minus the normal, and the angles are measured about it). For one marker the
// `unwrapped` vector is flattened: see the overload below.
int SignAndUnwrap(const std::vector<std::vector<double>>& raw, const std::vector<double>& x,
                  const std::vector<double>& weights, std::vector<std::vector<double>>* unwrapped);
// One marker.
int SignAndUnwrap(const std::vector<std::vector<double>>& raw, const std::vector<double>& x,
                  const std::vector<double>& weights, std::vector<double>* unwrapped);

// Weighted least-squares lines phi_mk = intercept_m + slope x_k with one slope for every marker (they turn
// with one rigid body) and one intercept per marker (its phase).
struct AngleLine {
  double slope = 1.0;
  std::vector<double> intercepts;
};
AngleLine FitAngleLine(const std::vector<std::vector<double>>& angles, const std::vector<double>& x,
                       const std::vector<double>& weights);

}  // namespace kincal::geometric
