#pragma once
// How far to trust an identified robot at a pose: the standard deviation of its predicted marker position,
//   sd(row) = sqrt(trace(J_row C J_row^T))                                                          (1)
// J_row: the 3 x p Jacobian of the row's predicted position with respect to the fit's free parameters
// (ErrorModelProblem::EvaluateRow, analytic), C: the fit's parameter covariance sigma^2 (J^T W J)^-1
// (error_model.h; here with a pseudo-inverse that leaves out directions below 1e-12 of the largest
// eigenvalue of the column-normalised J^T W J, so that a fit too ill-conditioned for the reported standard
// deviations still predicts with an sd). The trace, not the largest eigenvalue: sd^2 is then the expected squared
// length of the 3-D prediction error that comes from the parameters, the quantity a user compares with a 3-D error.
//
// The covariance travels in the identify report (details.prediction_covariance of the stage, written by
// every error-model estimator): parameter names, C in SI units of x (m, rad, the ratio scale, joint
// error coefficients' SI units), sigma (m, per residual), and the median sd over the training rows.
// `kincal predict --report REPORT.json` reads it back and maps it onto the robot's parameters by name.
// A row is outside what the training poses support when sd > kSupportFactor x the median training sd
// (3: a pose whose prediction is three times less certain than a typical training pose), or when one of
// its joint readings lies more than kJointMargin beyond the range the training rows covered on that
// joint. The second rule sees what the covariance cannot: a model's sd grows slowly outside the training
// range, while what the model lacks need not (fanuc_boby2021: the joint-2 stop 16 deg beyond the trained
// stops is 1.9 mm off with an sd of 0.19 mm, the arm's compliance).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "estimators/error_model/error_model.h"

namespace kincal {

struct PredictionCovariance {
  static constexpr double kSupportFactor = 3.0;
  std::vector<std::string> names;  // free parameters, x's order
  Eigen::MatrixXd matrix;          // p x p, SI
  double sigma = NAN;              // m, noise per residual
  double median_train_sd = NAN;    // m, median of (1) over the training rows
  // The training rows' joint readings, per joint: smallest and largest (rad; m for prismatic joints).
  // Empty in a report that does not record them (then only the sd rule applies).
  Eigen::VectorXd joint_min, joint_max;
  static constexpr double kJointMargin = 0.05;  // rad (m for prismatic joints): 2.9 deg
  double SupportThreshold() const { return kSupportFactor * median_train_sd; }
  // Outside the support: sd above SupportThreshold(), or a joint reading q beyond the training range.
  bool OutsideSupport(double sd, const Eigen::VectorXd& q) const;

  nlohmann::json ToJson() const;
  // Throws std::invalid_argument when a key is missing or the matrix does not match the names.
  static PredictionCovariance FromJson(const nlohmann::json& j);
};

// The covariance of a fit at its solution x, with the median training-row sd (one more pass).
PredictionCovariance ComputePredictionCovariance(const PreparedErrorModel& prep, const Eigen::VectorXd& x,
                                                 const RowWeighting& weighting);

// (1) for every row of `data` predicted by `model` (an identified robot) under `controller`; parameters of
// the covariance the model does not have (and the reverse) are left out. Throws std::invalid_argument
// like ErrorModelProblem for data the model cannot predict.
std::vector<double> PredictionSd(const Robot& model, const Robot& controller, const Dataset& data,
                                 const PredictionCovariance& covariance);

// Summary of a held-out set: rows outside the support, and the fraction of 3-D errors within
// 3 sqrt(sd^2 + sigma_3d^2) (the calibration check of (1)). sigma_3d = sqrt(3) sigma: the noise of a 3-D
// position (the trace of its covariance, like sd), so that sd^2 + sigma_3d^2 is the expected squared
// 3-D error. `coverage_1d` uses sigma per residual instead (a stricter check, reported beside it).
struct UncertaintyCheck {
  int rows = 0;
  int outside_support = 0;
  double coverage = NAN;
  double coverage_1d = NAN;
  double coverage_supported = NAN;  // `coverage` of the rows inside the support only (what the user is told to trust)
  nlohmann::json ToJson() const;
};
// `data`: the rows of `errors` and `sd` (their joint readings).
UncertaintyCheck CheckUncertainty(const std::vector<double>& errors, const std::vector<double>& sd,
                                  const PredictionCovariance& covariance, const Dataset& data);

}  // namespace kincal
