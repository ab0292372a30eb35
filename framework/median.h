#pragma once
// The median of a sample, one definition for kincal: of the finite values (NaN and infinities are left
// out: they break the ordering), the middle one, or the mean of the two middle ones for an even count;
// NaN when no value is finite.
#include <vector>

namespace kincal {

double Median(std::vector<double> values);

}  // namespace kincal
