#pragma once
// Kernel ridge regression (the mean of a Gaussian process) of a 3-D residual on joint angles:
// f(x) = mean + sum_i alpha_i k(x, x_i), with the squared-exponential kernel k = exp(-r^2 / 2) or the
// Matern 5/2 kernel k = (1 + sqrt(5) r + 5 r^2 / 3) exp(-sqrt(5) r) (Rasmussen and Williams eq. 4.17), r = |x - y|,
// alpha = (K + lambda I)^-1 (Y - mean) (Rasmussen and Williams 2006, eq. 2.25; lambda is the noise
// variance over the signal variance), with one length scale per joint (|x - y|^2 = sum_j (dx_j / l_j)^2).
// The length scales and lambda are chosen by K-fold cross-validation on the training rows only: a grid
// of one common length scale and lambda, then each joint's scale in turn.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace kincal_learned {

enum class Kernel { kSquaredExponential, kMatern52 };

struct KernelRidgeOptions {
  Kernel kernel = Kernel::kSquaredExponential;
  std::vector<double> length_scales = {0.15, 0.25, 0.4, 0.6, 0.9, 1.4, 2.0};  // rad
  std::vector<double> lambdas = {0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0};
  // Then per joint (automatic relevance determination): each joint's length scale multiplied by these
  // factors in turn, kept when the cross-validated error falls, for `ard_rounds` rounds over the joints.
  std::vector<double> ard_factors = {0.35, 0.6, 1.6, 3.0, 1000.0};  // 1000: the joint dropped
  int ard_rounds = 2;
  int folds = 5;
  uint64_t seed = 1;  // the folds' shuffle
};

class KernelRidge {
 public:
  KernelRidge() = default;
  // X: n x d inputs, Y: n x 3 targets. Chooses l and lambda by cross-validation, then fits on every row.
  void Fit(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const KernelRidgeOptions& options);
  // Fit with given hyper-parameters: one length scale per input column.
  void FitWith(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const Eigen::VectorXd& length_scales, double lambda,
               Kernel kernel);
  bool fitted() const { return X_.rows() > 0; }
  Eigen::Vector3d Predict(const Eigen::VectorXd& x) const;
  // d Predict / dx: 3 x d.
  Eigen::MatrixXd Gradient(const Eigen::VectorXd& x) const;

  const Eigen::VectorXd& length_scales() const { return length_scales_; }
  double lambda() const { return lambda_; }
  // Cross-validated RMS of the residual's norm at the chosen hyper-parameters, and with none (the mean).
  double cv_rms() const { return cv_rms_; }
  double cv_rms_mean_only() const { return cv_rms_mean_only_; }

 private:
  // K-fold cross-validated RMS of the residual's norm.
  double CrossValidate(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const Eigen::VectorXd& length_scales,
                       double lambda, Kernel kernel, const std::vector<int>& order, int folds, double* mean_only) const;

  Eigen::MatrixXd X_;      // n x d, divided by the length scales
  Eigen::MatrixXd alpha_;  // n x 3
  Eigen::Vector3d mean_ = Eigen::Vector3d::Zero();
  Eigen::VectorXd length_scales_;
  double lambda_ = 1.0;
  Kernel kernel_ = Kernel::kSquaredExponential;
  double cv_rms_ = 0.0;
  double cv_rms_mean_only_ = 0.0;
};

}  // namespace kincal_learned
