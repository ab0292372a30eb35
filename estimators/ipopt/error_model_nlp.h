#pragma once
// The error model as an Ipopt TNLP: n = the problem's free parameters in the scaled variables y of
// scaled_error_model.h, no constraints (m = 0), its bounds, objective f(y) = sum |r|^2 / f_unit, gradient
// 2 s .* J^T r / f_unit, Hessian (dense lower triangle) the Gauss-Newton 2 S J^T J S / f_unit. Ipopt asks
// for f, its gradient and the Hessian at the same point in turn, so the last pass over the data is cached
// with what it computed (cost < gradient < normal equations) and a request reuses it when it asks for no
// more.
#include <coin/IpTNLP.hpp>

#include <Eigen/Core>

#include "estimators/bounded/scaled_error_model.h"

namespace kincal {

class ErrorModelNlp final : public Ipopt::TNLP {
 public:
  // `model` (and its problem) must outlive the NLP.
  explicit ErrorModelNlp(const ScaledErrorModel& model);

  // The point finalize_solution received (x units), and Ipopt's verdict.
  const Eigen::VectorXd& solution() const { return solution_; }
  Ipopt::SolverReturn solver_return() const { return solver_return_; }
  int passes() const { return passes_; }  // passes over the data
  int parameters_at_bounds() const { return at_bounds_; }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* y_l, Ipopt::Number* y_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* y, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* y, bool new_x, Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* y, bool new_x, Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* y, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* y, bool new_x, Ipopt::Index m, Ipopt::Index nele_jac,
                  Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* y, bool new_x, Ipopt::Number obj_factor, Ipopt::Index m,
              const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele_hess, Ipopt::Index* iRow,
              Ipopt::Index* jCol, Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* y, const Ipopt::Number* z_L,
                         const Ipopt::Number* z_U, Ipopt::Index m, const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  // Makes the cache hold at least `what` at y; false when the cost is not finite.
  bool Ensure(const Ipopt::Number* y, Accumulate what);

  const ScaledErrorModel& model_;
  Eigen::VectorXd cached_y_;
  int cached_level_ = -1;  // static_cast<int>(Accumulate) of what the cache holds, -1: nothing
  NormalEquations cached_;
  int passes_ = 0;
  Eigen::VectorXd solution_;
  Ipopt::SolverReturn solver_return_ = Ipopt::UNASSIGNED;
  int at_bounds_ = 0;
};

}  // namespace kincal
