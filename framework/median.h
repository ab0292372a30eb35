#pragma once
// The median of a sample, one definition for kincal: of the finite values (NaN and infinities are left
// out: they break the ordering), the middle one, or the mean of the two middle ones for an even count;
// NaN when no value is finite.
#include <vector>

namespace kincal {

double Median(std::vector<double> values);

// The quantile f in [0, 1] of sorted values, interpolated linearly between the two nearest ranks
// (Hyndman and Fan's type 7, R's and NumPy's default): Quantile(sorted, 0.5) is the median above for
// finite values. `sorted` must be ascending, finite and not empty.
double Quantile(const std::vector<double>& sorted, double f);

}  // namespace kincal
