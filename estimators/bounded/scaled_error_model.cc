#include "estimators/bounded/scaled_error_model.h"

namespace kincal {

NamedBounds BoundsByName(const ErrorModelProblem& problem) {
  Eigen::VectorXd lower, upper;
  problem.Bounds(&lower, &upper);
  NamedBounds out;
  for (int i = 0; i < problem.num_parameters(); ++i) out[problem.parameters()[i].name] = {lower[i], upper[i]};
  return out;
}

ScaledErrorModel::ScaledErrorModel(const ErrorModelProblem& problem, const NormalEquations& at_start,
                                   const NamedBounds& original, const RowWeighting& weighting)
    : problem_(problem), weighting_(weighting), x_start_(problem.InitialX()), scale_(problem.CharacteristicScales()) {
  Eigen::VectorXd lower, upper;
  problem.Bounds(&lower, &upper);
  for (int i = 0; i < size(); ++i) {
    const auto it = original.find(problem.parameters()[i].name);
    if (it == original.end()) continue;
    lower[i] = it->second.first;
    upper[i] = it->second.second;
  }
  y_lower_ = Y(lower);
  y_upper_ = Y(upper);
  if (at_start.JtJ.rows() == size() && size() > 0) {
    const double mean = 2.0 * at_start.JtJ.diagonal().cwiseProduct(scale_.cwiseAbs2()).mean();
    if (mean > 0.0) f_unit_ = mean;
  }
}

Eigen::VectorXd ScaledErrorModel::X(const double* y) const {
  return x_start_ + scale_.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(y, size()));
}

Eigen::VectorXd ScaledErrorModel::Y(const Eigen::VectorXd& x) const { return (x - x_start_).cwiseQuotient(scale_); }

NormalEquations ScaledErrorModel::Evaluate(const double* y, Accumulate what) const {
  return AccumulateNormalEquations(problem_, X(y), weighting_, what);
}

int ScaledErrorModel::CountAtBounds(const double* y) const {
  int count = 0;
  for (int i = 0; i < size(); ++i) {
    const double margin = 1e-6 * (y_upper_[i] - y_lower_[i]);
    count += (y[i] <= y_lower_[i] + margin || y[i] >= y_upper_[i] - margin);
  }
  return count;
}

}  // namespace kincal
