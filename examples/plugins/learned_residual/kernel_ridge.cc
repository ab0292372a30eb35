#include "kernel_ridge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace kincal_learned {
namespace {

Eigen::MatrixXd SquaredDistances(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const Eigen::VectorXd a = A.rowwise().squaredNorm(), b = B.rowwise().squaredNorm();
  Eigen::MatrixXd D = (-2.0 * A * B.transpose()).colwise() + a;
  D.rowwise() += b.transpose();
  return D.cwiseMax(0.0);
}

Eigen::MatrixXd Rows(const Eigen::MatrixXd& M, const std::vector<int>& rows) {
  Eigen::MatrixXd out(rows.size(), M.cols());
  for (size_t i = 0; i < rows.size(); ++i) out.row(i) = M.row(rows[i]);
  return out;
}

// k(r^2) elementwise, and the factor g with d k / d x = g (x_i - x) in scaled units.
Eigen::ArrayXXd KernelOf(const Eigen::ArrayXXd& r2, Kernel kernel) {
  if (kernel == Kernel::kSquaredExponential) return (-0.5 * r2).exp();
  const Eigen::ArrayXXd sr = std::sqrt(5.0) * r2.sqrt();
  return (1.0 + sr + sr.square() / 3.0) * (-sr).exp();
}
Eigen::ArrayXd GradientFactor(const Eigen::ArrayXd& r2, Kernel kernel) {
  if (kernel == Kernel::kSquaredExponential) return (-0.5 * r2).exp();
  const Eigen::ArrayXd sr = std::sqrt(5.0) * r2.sqrt();
  return 5.0 / 3.0 * (1.0 + sr) * (-sr).exp();
}

}  // namespace

void KernelRidge::FitWith(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const Eigen::VectorXd& length_scales,
                          double lambda, Kernel kernel) {
  if (X.rows() != Y.rows() || Y.cols() != 3 || X.rows() == 0 || length_scales.size() != X.cols()) {
    throw std::invalid_argument("kernel ridge: bad shapes");
  }
  length_scales_ = length_scales;
  lambda_ = lambda;
  kernel_ = kernel;
  X_ = X * length_scales.cwiseInverse().asDiagonal();
  mean_ = Y.colwise().mean().transpose();
  Eigen::MatrixXd K = KernelOf(SquaredDistances(X_, X_).array(), kernel).matrix();
  K.diagonal().array() += lambda;
  alpha_ = K.llt().solve(Y.rowwise() - mean_.transpose());
}

double KernelRidge::CrossValidate(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                  const Eigen::VectorXd& length_scales, double lambda, Kernel kernel,
                                  const std::vector<int>& order, int folds, double* mean_only) const {
  const int n = static_cast<int>(X.rows());
  double sum2 = 0.0, sum2_mean = 0.0;
  for (int f = 0; f < folds; ++f) {
    std::vector<int> train, test;
    for (int i = 0; i < n; ++i) (i % folds == f ? test : train).push_back(order[i]);
    KernelRidge model;
    model.FitWith(Rows(X, train), Rows(Y, train), length_scales, lambda, kernel);
    for (int i : test) {
      sum2 += (Y.row(i).transpose() - model.Predict(X.row(i).transpose())).squaredNorm();
      sum2_mean += (Y.row(i).transpose() - model.mean_).squaredNorm();
    }
  }
  if (mean_only) *mean_only = std::sqrt(sum2_mean / n);
  return std::sqrt(sum2 / n);
}

void KernelRidge::Fit(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const KernelRidgeOptions& options) {
  const int n = static_cast<int>(X.rows()), d = static_cast<int>(X.cols());
  const int folds = std::max(2, std::min(options.folds, n));
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(options.seed);
  std::shuffle(order.begin(), order.end(), rng);
  double best = std::numeric_limits<double>::infinity(), best_lambda = options.lambdas.front(), mean_only = 0.0;
  Eigen::VectorXd best_scales = Eigen::VectorXd::Constant(d, options.length_scales.front());
  for (double l : options.length_scales) {
    for (double lambda : options.lambdas) {
      const Eigen::VectorXd scales = Eigen::VectorXd::Constant(d, l);
      const double rms = CrossValidate(X, Y, scales, lambda, options.kernel, order, folds, &mean_only);
      if (rms < best) best = rms, best_scales = scales, best_lambda = lambda;
    }
  }
  for (int round = 0; round < options.ard_rounds; ++round) {
    for (int j = 0; j < d; ++j) {
      const Eigen::VectorXd start = best_scales;
      for (double factor : options.ard_factors) {
        Eigen::VectorXd scales = start;
        scales[j] *= factor;
        for (double lambda : {best_lambda * 0.5, best_lambda, best_lambda * 2}) {
          const double rms = CrossValidate(X, Y, scales, lambda, options.kernel, order, folds, nullptr);
          if (rms < best) best = rms, best_scales = scales, best_lambda = lambda;
        }
      }
    }
  }
  FitWith(X, Y, best_scales, best_lambda, options.kernel);
  cv_rms_ = best;
  cv_rms_mean_only_ = mean_only;
}

Eigen::Vector3d KernelRidge::Predict(const Eigen::VectorXd& x) const {
  if (!fitted()) return Eigen::Vector3d::Zero();
  const Eigen::VectorXd xs = x.cwiseQuotient(length_scales_);
  const Eigen::VectorXd k = KernelOf((X_.rowwise() - xs.transpose()).rowwise().squaredNorm().array(), kernel_).matrix();
  return mean_ + alpha_.transpose() * k;
}

Eigen::MatrixXd KernelRidge::Gradient(const Eigen::VectorXd& x) const {
  if (!fitted()) return Eigen::MatrixXd::Zero(3, x.size());
  const Eigen::VectorXd xs = x.cwiseQuotient(length_scales_);
  const Eigen::MatrixXd diff = X_.rowwise() - xs.transpose();  // scaled x_i - x
  const Eigen::VectorXd k = GradientFactor(diff.rowwise().squaredNorm().array(), kernel_).matrix();
  // d k_i / dx_j = g_i (x_ij - x_j) / l_j (in scaled units, then once more 1 / l_j for x unscaled).
  const Eigen::MatrixXd dk = (diff.array().colwise() * k.array()).matrix() * length_scales_.cwiseInverse().asDiagonal();
  return alpha_.transpose() * dk;
}

}  // namespace kincal_learned
