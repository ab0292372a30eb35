#include "estimators/ipopt/error_model_nlp.h"

#include <cmath>

namespace kincal {

using Ipopt::Index;
using Ipopt::Number;

ErrorModelNlp::ErrorModelNlp(const ScaledErrorModel& model) : model_(model) {
  const Eigen::VectorXd y0 = Eigen::VectorXd::Zero(model.size());
  solution_ = model.X(y0.data());
}

bool ErrorModelNlp::Ensure(const Number* y, Accumulate what) {
  const int n = model_.size();
  const Eigen::Map<const Eigen::VectorXd> y_map(y, n);
  if (cached_level_ < static_cast<int>(what) || cached_y_.size() != n || cached_y_ != y_map) {
    cached_ = model_.Evaluate(y, what);
    cached_y_ = y_map;
    cached_level_ = static_cast<int>(what);
    ++passes_;
  }
  return std::isfinite(cached_.cost);
}

bool ErrorModelNlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) {
  n = static_cast<Index>(model_.size());
  m = 0;
  nnz_jac_g = 0;
  nnz_h_lag = n * (n + 1) / 2;  // dense lower triangle
  index_style = C_STYLE;
  return true;
}

bool ErrorModelNlp::get_bounds_info(Index n, Number* y_l, Number* y_u, Index /*m*/, Number* /*g_l*/, Number* /*g_u*/) {
  Eigen::Map<Eigen::VectorXd>(y_l, n) = model_.y_lower();
  Eigen::Map<Eigen::VectorXd>(y_u, n) = model_.y_upper();
  return true;
}

bool ErrorModelNlp::get_starting_point(Index n, bool init_x, Number* y, bool init_z, Number* /*z_L*/, Number* /*z_U*/,
                                       Index /*m*/, bool init_lambda, Number* /*lambda*/) {
  if (init_z || init_lambda) return false;  // no warm start
  if (init_x) Eigen::Map<Eigen::VectorXd>(y, n).setZero();
  return true;
}

bool ErrorModelNlp::eval_f(Index /*n*/, const Number* y, bool /*new_x*/, Number& obj_value) {
  if (!Ensure(y, Accumulate::kCost)) return false;
  obj_value = model_.Cost(cached_);
  return true;
}

bool ErrorModelNlp::eval_grad_f(Index n, const Number* y, bool /*new_x*/, Number* grad_f) {
  if (!Ensure(y, Accumulate::kGradient)) return false;
  Eigen::Map<Eigen::VectorXd>(grad_f, n) = model_.Gradient(cached_);
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
                           const Number* /*lambda*/, bool /*new_lambda*/, Index /*nele_hess*/, Index* iRow, Index* jCol,
                           Number* values) {
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
  const Eigen::MatrixXd H = obj_factor * model_.Hessian(cached_);
  Index k = 0;
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j <= i; ++j, ++k) values[k] = H(i, j);
  }
  return true;
}

void ErrorModelNlp::finalize_solution(Ipopt::SolverReturn status, Index /*n*/, const Number* y, const Number* /*z_L*/,
                                      const Number* /*z_U*/, Index /*m*/, const Number* /*g*/, const Number* /*lambda*/,
                                      Number /*obj_value*/, const Ipopt::IpoptData* /*ip_data*/,
                                      Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) {
  solver_return_ = status;
  solution_ = model_.X(y);
  at_bounds_ = model_.CountAtBounds(y);
}

}  // namespace kincal
