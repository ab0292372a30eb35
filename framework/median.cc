#include "framework/median.h"

#include <algorithm>
#include <cmath>

namespace kincal {

double Median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  if (values.empty()) return NAN;
  const size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(half), values.end());
  const double upper = values[half];
  if (values.size() % 2) return upper;
  // The lower middle: the largest of the values before the upper one.
  return 0.5 * (*std::max_element(values.begin(), values.begin() + static_cast<long>(half)) + upper);
}

double Quantile(const std::vector<double>& sorted, double f) {
  const double pos = f * static_cast<double>(sorted.size() - 1);
  const size_t i = static_cast<size_t>(std::floor(pos));
  if (i + 1 >= sorted.size()) return sorted.back();
  return sorted[i] + (pos - static_cast<double>(i)) * (sorted[i + 1] - sorted[i]);
}

}  // namespace kincal
