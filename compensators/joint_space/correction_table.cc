#include "compensators/joint_space/correction_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kincal {
namespace {

constexpr int kMaxAxes = 16;

// Interpolation weights along one axis: up to 4 (node, weight) pairs.
struct AxisWeights {
  int count = 0;
  int64_t index[4];
  double weight[4];
  void Add(int64_t i, double w) {
    for (int k = 0; k < count; ++k) {
      if (index[k] == i) {
        weight[k] += w;
        return;
      }
    }
    index[count] = i;
    weight[count] = w;
    ++count;
  }
};

}  // namespace

CorrectionTable::CorrectionTable(std::vector<Axis> axes, int value_size)
    : axes_(std::move(axes)), value_size_(value_size) {
  if (axes_.empty() || axes_.size() > kMaxAxes) throw std::invalid_argument("correction table: 1 to 16 axes");
  if (value_size_ < 1) throw std::invalid_argument("correction table: empty values");
  num_nodes_ = 1;
  for (const Axis& a : axes_) {
    if (a.points < 2) throw std::invalid_argument("correction table: an axis needs at least 2 points");
    if (!(a.high > a.low)) throw std::invalid_argument("correction table: an axis needs a non-empty range");
    strides_.push_back(num_nodes_);
    num_nodes_ *= a.points;
  }
  values_.assign(static_cast<size_t>(num_nodes_ * value_size_), 0.0);
  flags_.assign(static_cast<size_t>(num_nodes_), 0);
}

double CorrectionTable::MemoryBytes(const std::vector<Axis>& axes, int value_size) {
  double nodes = 1;
  for (const Axis& a : axes) nodes *= a.points;
  return nodes * (value_size * sizeof(double) + 1);
}

void CorrectionTable::NodeJoints(int64_t node, Eigen::VectorXd* q) const {
  for (size_t a = 0; a < axes_.size(); ++a) {
    const Axis& axis = axes_[a];
    const int64_t k = (node / strides_[a]) % axis.points;
    // The last node is exactly `high`, not low + (points - 1) * step rounded.
    (*q)[axis.joint] = k == axis.points - 1 ? axis.high : axis.low + k * (axis.high - axis.low) / (axis.points - 1);
  }
}

int64_t CorrectionTable::num_flagged() const { return std::count(flags_.begin(), flags_.end(), 1); }

CorrectionTable::Lookup CorrectionTable::Interpolate(const Eigen::VectorXd& q, Interpolation interpolation,
                                                     double* out) const {
  Lookup lookup;
  const int d = static_cast<int>(axes_.size());
  AxisWeights w[kMaxAxes];
  for (int a = 0; a < d; ++a) {
    const Axis& axis = axes_[a];
    const double step = (axis.high - axis.low) / (axis.points - 1);
    double x = q[axis.joint];
    if (!(x >= axis.low && x <= axis.high)) {
      lookup.inside = false;
      x = std::clamp(std::isfinite(x) ? x : axis.low, axis.low, axis.high);
    }
    const double s = (x - axis.low) / step;
    const int64_t cell = std::min<int64_t>(static_cast<int64_t>(s), axis.points - 2);
    const double t = s - cell;
    const int64_t last = axis.points - 1;
    if (interpolation == Interpolation::kLinear) {
      w[a].Add(cell, 1.0 - t);
      w[a].Add(cell + 1, t);
      continue;
    }
    const double t2 = t * t, t3 = t2 * t;
    const double cubic[4] = {0.5 * (-t3 + 2 * t2 - t), 0.5 * (3 * t3 - 5 * t2 + 2), 0.5 * (-3 * t3 + 4 * t2 + t),
                             0.5 * (t3 - t2)};
    for (int k = 0; k < 4; ++k) {
      const int64_t i = cell - 1 + k;
      if (i < 0) {  // ghost node 2 p_0 - p_1
        w[a].Add(0, 2 * cubic[k]);
        w[a].Add(1, -cubic[k]);
      } else if (i > last) {  // ghost node 2 p_last - p_(last-1)
        w[a].Add(last, 2 * cubic[k]);
        w[a].Add(last - 1, -cubic[k]);
      } else {
        w[a].Add(i, cubic[k]);
      }
    }
  }
  std::fill(out, out + value_size_, 0.0);
  int digit[kMaxAxes] = {0};
  while (true) {
    double weight = 1.0;
    int64_t node = 0;
    for (int a = 0; a < d; ++a) {
      weight *= w[a].weight[digit[a]];
      node += w[a].index[digit[a]] * strides_[a];
    }
    if (weight != 0.0) {
      const double* v = values(node);
      for (int k = 0; k < value_size_; ++k) out[k] += weight * v[k];
      if (flags_[node]) lookup.flagged = true;
    }
    int a = 0;
    while (a < d && ++digit[a] == w[a].count) digit[a++] = 0;
    if (a == d) break;
  }
  return lookup;
}

}  // namespace kincal
