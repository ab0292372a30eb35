#pragma once
// Cost, gradient and Gauss-Newton normal equations of an ErrorModelProblem, accumulated row by row so
// that memory is O(p^2) whatever the number of rows (a million poses fit): rows are packed into a block
// of at most kBlockResiduals residuals and added with one symmetric rank-k update (BLAS-3 speed without
// ever holding J).
//
// Weighting (solver-side): row i has weight w_i (default 1) and a robust loss rho applied to its squared
// residual norm s_i = |r_i|^2 (the 3 or 6 residuals of the row together, Ceres' convention):
//   cost   = sum_i w_i rho(s_i)
//   J^T r  = sum_i w_i rho'(s_i) J_i^T r_i              (half the gradient of cost)
//   J^T J  = sum_i w_i rho'(s_i) J_i^T J_i              (IRLS: iteratively reweighted least squares)
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimators/error_model/error_model_problem.h"

namespace kincal {

struct RobustLoss {
  enum class Type { kNone, kHuber, kCauchy };
  Type type = Type::kNone;
  double scale = 1e-4;  // m: the residual norm c where the loss leaves the quadratic
  // rho(s), rho'(s) and rho''(s):
  //   none   s, 1, 0;
  //   huber  s for s <= c^2, else 2 c sqrt(s) - c^2;  rho' = min(1, c / sqrt(s));  rho'' = 0, else -rho' / (2 s);
  //   cauchy c^2 log(1 + s / c^2);                   rho' = 1 / (1 + s / c^2);     rho'' = -rho'^2 / c^2.
  // The one definition every backend applies (Ceres through a LossFunction that calls it).
  void Evaluate(double s, double* rho, double* rho_prime, double* rho_second = nullptr) const;
  // "none", "huber", "cauchy"; throws std::invalid_argument otherwise.
  static Type TypeFromName(const std::string& name);
};

struct RowWeighting {
  std::vector<double> weights;  // one per row, >= 0; empty means all 1
  RobustLoss loss;
  double weight(int row) const { return weights.empty() ? 1.0 : weights[row]; }
};

struct NormalEquations {
  Eigen::MatrixXd JtJ;            // p x p, symmetric (both triangles), empty unless requested
  Eigen::VectorXd Jtr;            // p, empty unless requested
  double cost = 0.0;              // sum w rho(s), plus prior_cost
  double prior_cost = 0.0;        // sum over parameters with a prior of (noise (x_j - mu_j) / sd_j)^2
  double irls_squares = 0.0;      // sum w rho'(s) s: the weighted sum of squares behind J^T J (sigma^2)
  double position_squares = 0.0;  // sum |r_position|^2, unweighted (the position RMS)
  int num_rows = 0;
  int num_residuals = 0;       // of the rows with a positive weight (the m of sigma^2)
  // What AddPriorTerms added to, as the data left it: the cost, J^T r and the diagonal of J^T J
  // (WithoutPriors); set by its first call.
  bool prior_terms_added = false;
  double data_cost = 0.0;
  Eigen::VectorXd data_Jtr, data_JtJ_diagonal;
  double PositionRms() const;  // m
};

enum class Accumulate { kCost, kGradient, kNormalEquations };

// Throws std::invalid_argument if weighting.weights has the wrong size or a negative/non-finite entry.
// with_prior: the parameters' priors (ErrorModelParameter::prior_sd, weighed by problem.prior_noise())
// add their pseudo-residuals noise (x_j - mu_j) / sd_j: to cost, J^T r and the diagonal of J^T J; never
// to irls_squares, position_squares or num_residuals, which describe the data alone.
NormalEquations AccumulateNormalEquations(const ErrorModelProblem& problem, const Eigen::VectorXd& x,
                                          const RowWeighting& weighting = RowWeighting(),
                                          Accumulate what = Accumulate::kNormalEquations, bool with_prior = true);

// The prior terms above, added to *ne (its Jtr and JtJ where they are sized for x).
void AddPriorTerms(const ErrorModelProblem& problem, const Eigen::VectorXd& x, NormalEquations* ne);
// What AccumulateNormalEquations returns with with_prior = false at the same x, to the bit, from what it
// returned with the priors (ne itself when no prior term was added).
NormalEquations WithoutPriors(const NormalEquations& ne);
// Per free parameter, what its prior adds to the diagonal of J^T J: (noise / sd)^2, 0 without a prior.
Eigen::VectorXd PriorInformation(const ErrorModelProblem& problem);

}  // namespace kincal
