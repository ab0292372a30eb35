#include "estimators/ipopt/error_model_nlp.h"

#include <cmath>

namespace kincal {

using Ipopt::Index;
using Ipopt::Number;

ErrorModelNlp::ErrorModelNlp(const ErrorModelProblem& problem, double f_unit)
    : problem_(problem), x_start_(problem.InitialX()), scale_(problem.CharacteristicScales()), f_unit_(f_unit) {
  Eigen::VectorXd lower, upper;
  problem.Bounds(&lower, &upper);
  y_lower_ = Y(lower);
  y_upper_ = Y(upper);
  solution_ = x_start_;
}

Eigen::VectorXd ErrorModelNlp::X(const double* y) const {
  return x_start_ + scale_.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(y, x_start_.size()));
}

Eigen::VectorXd ErrorModelNlp::Y(const Eigen::VectorXd& x) const { return (x - x_start_).cwiseQuotient(scale_); }

bool ErrorModelNlp::Ensure(const Number* y, Accumulate what) {
  const int n = static_cast<int>(x_start_.size());
  const Eigen::Map<const Eigen::VectorXd> y_map(y, n);
  if (cached_level_ < static_cast<int>(what) || cached_y_.size() != n || cached_y_ != y_map) {
    cached_ = AccumulateNormalEquations(problem_, X(y), RowWeighting(), what);
    cached_y_ = y_map;
    cached_level_ = static_cast<int>(what);
    ++passes_;
  }
  return std::isfinite(cached_.cost);
}

bool ErrorModelNlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                                 IndexStyleEnum& index_style) {
  n = static_cast<Index>(x_start_.size());
  m = 0;
  nnz_jac_g = 0;
  nnz_h_lag = n * (n + 1) / 2;  // dense lower triangle
  index_style = C_STYLE;
  return true;
}

bool ErrorModelNlp::get_bounds_info(Index n, Number* y_l, Number* y_u, Index /*m*/, Number* /*g_l*/,
                                    Number* /*g_u*/) {
  Eigen::Map<Eigen::VectorXd>(y_l, n) = y_lower_;
  Eigen::Map<Eigen::VectorXd>(y_u, n) = y_upper_;
  return true;
}

bool ErrorModelNlp::get_starting_point(Index n, bool init_x, Number* y, bool init_z, Number* /*z_L*/,
                                       Number* /*z_U*/, Index /*m*/, bool init_lambda, Number* /*lambda*/) {
  if (init_z || init_lambda) return false;  // no warm start
  if (init_x) Eigen::Map<Eigen::VectorXd>(y, n).setZero();
  return true;
}

bool ErrorModelNlp::eval_f(Index /*n*/, const Number* y, bool /*new_x*/, Number& obj_value) {
  if (!Ensure(y, Accumulate::kCost)) return false;
  obj_value = cached_.cost / f_unit_;
  return true;
}

bool ErrorModelNlp::eval_grad_f(Index n, const Number* y, bool /*new_x*/, Number* grad_f) {
  if (!Ensure(y, Accumulate::kGradient)) return false;
  Eigen::Map<Eigen::VectorXd>(grad_f, n) = (2.0 / f_unit_) * cached_.Jtr.cwiseProduct(scale_);
  return true;
}

bool ErrorModelNlp::eval_g(Index /*n*/, const Number* /*y*/, bool /*new_x*/, Index /*m*/, Number* /*g*/) {
  return true;
}

bool ErrorModelNlp::eval_jac_g(Index /*n*/, const Number* /*y*/, bool /*new_x*/, Index /*m*/, Index /*nele_jac*/,
                               Index* /*iRow*/, Index* /*jCol*/, Number* /*values*/) {
  return true;
}

bool ErrorModelNlp::eval_h(Index n, const Number* y, bool /*new_x*/, Number obj_factor, Index /*m*/,
                           const Number* /*lambda*/, bool /*new_lambda*/, Index /*nele_hess*/, Index* iRow,
                           Index* jCol, Number* values) {
  if (!values) {
    Index k = 0;
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j <= i; ++j, ++k) {
        iRow[k] = i;
        jCol[k] = j;
      }
    }
    return true;
  }
  if (!Ensure(y, Accumulate::kNormalEquations)) return false;
  const double factor = 2.0 * obj_factor / f_unit_;
  Index k = 0;
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j <= i; ++j, ++k) values[k] = factor * scale_[i] * cached_.JtJ(i, j) * scale_[j];
  }
  return true;
}

void ErrorModelNlp::finalize_solution(Ipopt::SolverReturn status, Index n, const Number* y, const Number* /*z_L*/,
                                      const Number* /*z_U*/, Index /*m*/, const Number* /*g*/,
                                      const Number* /*lambda*/, Number /*obj_value*/,
                                      const Ipopt::IpoptData* /*ip_data*/,
                                      Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) {
  solver_return_ = status;
  solution_ = X(y);
  // "On a bound": within a millionth of the bound's width (an interior point never touches it).
  at_bounds_ = 0;
  for (Index i = 0; i < n; ++i) {
    const double margin = 1e-6 * (y_upper_[i] - y_lower_[i]);
    at_bounds_ += (y[i] <= y_lower_[i] + margin || y[i] >= y_upper_[i] - margin);
  }
}

}  // namespace kincal
