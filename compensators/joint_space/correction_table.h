#pragma once
// CorrectionTable: vectors stored on a regular grid over some of the joints, interpolated by tensor
// products, multilinear (2^d nodes) or Catmull-Rom cubic (4^d nodes, C1, exact for quadratics; at the
// grid's edges the missing neighbour is extrapolated linearly, 2 p_0 - p_1).
// The joints not on the grid are ignored at lookup: the table assumes its values do not depend on them.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace kincal {

class CorrectionTable {
 public:
  enum class Interpolation { kLinear, kCubic };
  struct Axis {
    int joint = 0;  // 0-based joint index
    double low = 0.0, high = 0.0;
    int points = 2;  // >= 2, nodes at low + k (high - low) / (points - 1)
  };
  struct Lookup {
    bool inside = true;    // false: some joint lay outside its axis and was clamped to the edge
    bool flagged = false;  // a node used by the interpolation was flagged (its value is unreliable)
  };

  CorrectionTable() = default;
  // Throws std::invalid_argument for an axis with fewer than 2 points or an empty range.
  CorrectionTable(std::vector<Axis> axes, int value_size);

  const std::vector<Axis>& axes() const { return axes_; }
  int value_size() const { return value_size_; }
  int64_t num_nodes() const { return num_nodes_; }
  // Bytes of the values and flags.
  size_t memory_bytes() const { return values_.size() * sizeof(double) + flags_.size(); }
  // Bytes a table of these dimensions would take, without building it.
  static double MemoryBytes(const std::vector<Axis>& axes, int value_size);

  // The joint values of node `node`, written into the axes' joints of *q (other entries untouched).
  void NodeJoints(int64_t node, Eigen::VectorXd* q) const;
  double* values(int64_t node) { return values_.data() + node * value_size_; }
  const double* values(int64_t node) const { return values_.data() + node * value_size_; }
  void Flag(int64_t node) { flags_[node] = 1; }
  int64_t num_flagged() const;

  // Interpolated value at the joints q (full joint vector) into out[0..value_size).
  Lookup Interpolate(const Eigen::VectorXd& q, Interpolation interpolation, double* out) const;

 private:
  std::vector<Axis> axes_;
  std::vector<int64_t> strides_;  // node index = sum over axes of index_a * stride_a (first axis fastest)
  int value_size_ = 0;
  int64_t num_nodes_ = 0;
  std::vector<double> values_;
  std::vector<uint8_t> flags_;
};

}  // namespace kincal
