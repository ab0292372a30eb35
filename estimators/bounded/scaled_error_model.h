#pragma once
// The error model as the bounded solvers (nlopt, ipopt) see it, with the estimator's row weighting:
// scaled variables
// y = (x - x_start) / s (s: ErrorModelProblem::CharacteristicScales, 1 mm, 1 mrad, 1e-3 ratio scale) and
// the cost sum |r|^2 in units of its mean curvature in y at the start, f_unit = trace(2 S J^T J S) / p, so
// that the Gauss-Newton Hessian in y has eigenvalues around 1 (the size of a quasi-Newton method's initial
// identity Hessian) and the optimiser sees O(1) numbers whatever the units.
//
// Bounds are those of the problem the estimation started with (ErrorModelProblem::Bounds around the
// registered start), kept by parameter name when identifiability is re-analysed at a first solution:
// the re-analysed problem starts from that solution, and bounds around it would let a parameter walk
// one bound width per re-analysis.
#include <map>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/normal_equations.h"

namespace kincal {

using NamedBounds = std::map<std::string, std::pair<double, double>>;  // name -> (lower, upper), x units

NamedBounds BoundsByName(const ErrorModelProblem& problem);

class ScaledErrorModel {
 public:
  // `at_start`: normal equations of `problem` at its InitialX() with `weighting` (PreparedErrorModel::
  // initial). Bounds of parameters named in `original` are taken from it, the others from problem.Bounds().
  ScaledErrorModel(const ErrorModelProblem& problem, const NormalEquations& at_start, const NamedBounds& original,
                   const RowWeighting& weighting = RowWeighting());

  int size() const { return static_cast<int>(x_start_.size()); }
  Eigen::VectorXd X(const double* y) const;
  Eigen::VectorXd Y(const Eigen::VectorXd& x) const;
  const Eigen::VectorXd& scale() const { return scale_; }
  const Eigen::VectorXd& y_lower() const { return y_lower_; }
  const Eigen::VectorXd& y_upper() const { return y_upper_; }
  double f_unit() const { return f_unit_; }

  // Cost sum w rho(|r|^2) (and, as asked, J^T W r, J^T W J: normal_equations.h) at y, one pass over the
  // data, in x's units.
  NormalEquations Evaluate(const double* y, Accumulate what) const;
  // Scaled cost, gradient and Gauss-Newton Hessian in y from normal equations in x's units.
  double Cost(const NormalEquations& ne) const { return ne.cost / f_unit_; }
  Eigen::VectorXd Gradient(const NormalEquations& ne) const { return (2.0 / f_unit_) * ne.Jtr.cwiseProduct(scale_); }
  Eigen::MatrixXd Hessian(const NormalEquations& ne) const {
    return (2.0 / f_unit_) * (scale_.asDiagonal() * ne.JtJ * scale_.asDiagonal());
  }
  // Entries of y within a millionth of their bound's width from a bound.
  int CountAtBounds(const double* y) const;

 private:
  const ErrorModelProblem& problem_;
  RowWeighting weighting_;
  Eigen::VectorXd x_start_, scale_, y_lower_, y_upper_;
  double f_unit_ = 1.0;
};

}  // namespace kincal
