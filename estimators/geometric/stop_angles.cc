#include "estimators/geometric/stop_angles.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace kincal::geometric {
namespace {

// Angles of one marker with sign `sign`, unwrapped step by step in the order of x, each step the reading's
// turn plus the measured difference from it, reduced to (-pi, pi].
std::vector<double> Unwrap(const std::vector<double>& raw, const std::vector<double>& x, const std::vector<int>& order,
                           double sign) {
  std::vector<double> out(raw.size(), 0.0);
  out[order[0]] = sign * raw[order[0]];
  for (size_t k = 1; k < order.size(); ++k) {
    const int a = order[k - 1], b = order[k];
    const double dx = x[b] - x[a];
    out[b] = out[a] + dx + std::remainder(sign * (raw[b] - raw[a]) - dx, 2 * M_PI);
  }
  return out;
}

// Weighted sum of squares of (phi - x) about each marker's mean: how far the angles are from following the
// readings one to one.
double Disagreement(const std::vector<std::vector<double>>& angles, const std::vector<double>& x,
                    const std::vector<double>& weights) {
  double total = 0.0;
  for (size_t m = 0; m < angles.size(); ++m) {
    double mean = 0.0;
    for (size_t k = 0; k < x.size(); ++k) mean += angles[m][k] - x[k];
    mean /= static_cast<double>(x.size());
    double ss = 0.0;
    for (size_t k = 0; k < x.size(); ++k) ss += std::pow(angles[m][k] - x[k] - mean, 2);
    total += weights[m] * ss;
  }
  return total;
}

}  // namespace

int SignAndUnwrap(const std::vector<std::vector<double>>& raw, const std::vector<double>& x,
                  const std::vector<double>& weights, std::vector<std::vector<double>>* unwrapped) {
  std::vector<int> order(x.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return x[a] < x[b]; });
  std::vector<std::vector<double>> plus, minus;
  for (const auto& r : raw) {
    plus.push_back(Unwrap(r, x, order, 1.0));
    minus.push_back(Unwrap(r, x, order, -1.0));
  }
  // Ties (no marker moved) keep the normal as given.
  if (Disagreement(minus, x, weights) < Disagreement(plus, x, weights)) {
    *unwrapped = std::move(minus);
    return -1;
  }
  *unwrapped = std::move(plus);
  return 1;
}

int SignAndUnwrap(const std::vector<std::vector<double>>& raw, const std::vector<double>& x,
                  const std::vector<double>& weights, std::vector<double>* unwrapped) {
  std::vector<std::vector<double>> all;
  const int sign = SignAndUnwrap(raw, x, weights, &all);
  *unwrapped = all.at(0);
  return sign;
}

AngleLine FitAngleLine(const std::vector<std::vector<double>>& angles, const std::vector<double>& x,
                       const std::vector<double>& weights) {
  const double n = static_cast<double>(x.size());
  const double x_mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  std::vector<double> means;
  double sxx = 0.0, sxy = 0.0;
  for (size_t m = 0; m < angles.size(); ++m) {
    const double mean = std::accumulate(angles[m].begin(), angles[m].end(), 0.0) / n;
    means.push_back(mean);
    for (size_t k = 0; k < x.size(); ++k) {
      sxx += weights[m] * (x[k] - x_mean) * (x[k] - x_mean);
      sxy += weights[m] * (x[k] - x_mean) * (angles[m][k] - mean);
    }
  }
  AngleLine line;
  line.slope = sxy / sxx;
  for (double mean : means) line.intercepts.push_back(mean - line.slope * x_mean);
  return line;
}

}  // namespace kincal::geometric
