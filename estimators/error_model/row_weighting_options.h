#pragma once
// The robust-loss and per-row-weight options that the unbounded least-squares estimators (least_squares,
// ceres) share, with one meaning (normal_equations.h: cost = sum_i w_i rho(|r_i|^2)) and one set of keys.
#include <string>
#include <vector>

#include "estimators/error_model/normal_equations.h"
#include "framework/registry.h"

namespace kincal {

struct RowWeightingOptions {
  std::string loss = "none";    // "none", "huber" or "cauchy"
  double loss_scale = 1e-4;     // m, where the loss leaves the quadratic (YAML: a length, e.g. 0.1mm)
  std::vector<double> weights;  // one per dataset row (>= 0); empty = all 1

  // Keys loss, loss_scale, weights.
  static const OptionTable<RowWeightingOptions>& Table();
  bool IsValid(std::string* why) const;
  // The weighting of a dataset of `num_rows` rows; throws std::invalid_argument naming `estimator` when
  // weights are given but not one per row.
  RowWeighting Weighting(size_t num_rows, const std::string& estimator) const;
};

}  // namespace kincal
