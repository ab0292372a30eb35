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
// (1) is the parameters' part only: it says how far the estimate could move within the model, never what
// the model lacks (an arm's compliance where the file has no gravity term, a thermal drift), which
// the training residuals partly absorb into sigma and which grows where the training poses do not reach.
// The reported sd adds a model-inadequacy variance tau^2, measured out of sample:
//   sd_pred(row)^2 = sd(row)^2 + tau(row)^2                                                        (2)
// tau^2 is what the blocked K-fold cross-validation of the training rows (model_selection.h, the same
// folds and the same held-out predictions as the selection's CV RMS) sees beyond what the bound already
// explains. In fold k the candidate is fitted on the other blocks (the selection's one Gauss-Newton step),
// with noise estimate sigma_k and covariance C_k = sigma_k^2 A_k^+ of that step (the training rows' normal
// equations, the pseudo-inverse of (1)); if the bound were right, a held-out row i's 3-D error e_i would
// have E|e_i|^2 = E_i = 3 sigma_k^2 + sd_k(i)^2 ((1) with C_k). tau^2 is the variance that is missing,
// x_i = |e_i|^2 - E_i, averaged with inverse-variance weights (|e|^2 of a Gaussian 3-D error has a variance
// proportional to the square of its mean, (E_i + tau^2)^2), to a fixed point from tau^2 = 0:
//   tau^2 = max(0, sum_i w_i x_i / sum_i w_i),  w_i = 1 / (E_i + tau^2)^2                           (3)
// Why this quantity: the bound 3 sqrt(sd_pred^2 + sigma_3d^2) is applied, with the fit's own sigma and
// covariance, to rows the fit did not see; (3) is the shortfall of exactly that bound's variance on rows
// the fold's fit did not see, in the fold's own sigma and covariance, so that what sigma absorbs in sample
// (the part of the model's inadequacy the training rows show) is not counted twice, and the parameters'
// part, larger in a fold (fewer rows), is not taken for inadequacy. The weights matter: a block that holds
// out a whole joint's sweep leaves directions the other rows barely determine, its rows' sd_k reaches
// tens of mm, and a plain mean of x_i would be swamped by the noise of those rows.
// tau depends on the row in the one way the folds measure: the rows beyond the fold's training range on
// joint j (the joint-range rule below, kJointMargin) give tau_j, the rows within range on every joint give
// tau; a row gets the largest of tau and the tau_j of the joints it lies beyond the training range on.
// The real data call for it (docs/guide/real_data.md): a fold that holds out the end of a joint's sweep
// predicts its stop far outside the bound while the rows within range match theirs; pooled, the many
// precise rows within range outweigh the few beyond it. What the model lacks (compliance)
// grows where the training poses do not reach, and on the joint that leaves its range. Finer laws (tau
// growing with the distance) would rest on the few rows each fold holds beyond its range; per joint and
// within/beyond is what they support. Neither the support flags nor the fitted parameters change.
// Without cross-validation (no `select`) tau is 0 and the report says so (inadequacy_source "none": the sd
// is the parameters' part only), unless the options ask `cross_validate: true`: the same folds, each
// fitting the model itself with the estimator's options (no step), (3) for that model alone. It costs K
// more fits, which a plain fit should not pay unasked (studies run thousands of them); a user who wants the
// bound to hold on poses the model does not represent asks for it, and identify says which sd it printed.
//
// The covariance travels in the identify report (details.prediction_covariance of the stage, written by
// every error-model estimator): parameter names, C in SI units of x (m, rad, the ratio scale, joint
// error coefficients' SI units), sigma (m, per residual), and the median sd over the training rows.
// `kincal predict --report REPORT.json` reads it back and maps it onto the robot's parameters by name.
// A row is outside what the training poses support when sd > kSupportFactor x the median training sd
// (3: a pose whose prediction is three times less certain than a typical training pose), or when one of
// its joint readings lies more than kJointMargin beyond the range the training rows covered on that
// joint. The second rule sees what the covariance cannot: a model's sd grows slowly outside the training
// range, while what the model lacks need not (docs/guide/methods.md gives the case).
#include <cmath>
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
  double inadequacy = 0.0;         // m, tau of (2) within the training joint range; 0 in a report without it
  // m, per joint j: tau of (2) for a row with joint j beyond the training range; empty in a report without it.
  std::vector<double> inadequacy_beyond;
  std::string inadequacy_source = "none";  // "cross-validation of the selection", "cross-validation", "none"
  // The training rows' joint readings, per joint: smallest and largest (rad; m for prismatic joints).
  // Empty in a report that does not record them (then only the sd rule applies).
  Eigen::VectorXd joint_min, joint_max;
  static constexpr double kJointMargin = 0.05;  // rad (m for prismatic joints): 2.9 deg
  double SupportThreshold() const { return kSupportFactor * median_train_sd; }
  // Outside the support: sd above SupportThreshold(), or a joint reading q beyond the training range.
  bool OutsideSupport(double sd, const Eigen::VectorXd& q) const;
  bool BeyondJointRange(const Eigen::VectorXd& q) const;
  // tau at a row: the largest of `inadequacy` and inadequacy_beyond of the joints q lies beyond the range on.
  double Inadequacy(const Eigen::VectorXd& q) const;
  // (2) at a row with joint readings q from its parameters' part sd (1).
  double PredictedSd(double sd, const Eigen::VectorXd& q) const {
    const double tau = Inadequacy(q);
    return std::sqrt(sd * sd + tau * tau);
  }

  nlohmann::json ToJson() const;
  // Throws std::invalid_argument when a key is missing or the matrix does not match the names.
  static PredictionCovariance FromJson(const nlohmann::json& j);
};

// One line for a terminal: tau within the training range and per joint beyond it, and where it comes from
// (or that the sd is the parameters' part only).
std::string InadequacySummary(const PredictionCovariance& covariance);

// The covariance of a fit at its solution x, with the median training-row sd (one more pass).
PredictionCovariance ComputePredictionCovariance(const PreparedErrorModel& prep, const Eigen::VectorXd& x,
                                                 const RowWeighting& weighting);

// (1) for every row of `data` predicted by `model` (an identified robot) under `controller`; parameters of
// the covariance the model does not have (and the reverse) are left out. Throws std::invalid_argument
// like ErrorModelProblem for data the model cannot predict.
std::vector<double> PredictionSd(const Robot& model, const Robot& controller, const Dataset& data,
                                 const PredictionCovariance& covariance);

// The held-out rows of a cross-validation, for (3): |e|^2 (m^2), E = 3 sigma_k^2 + sd_k^2 (m^2), and
// whether a joint reading lay beyond the fold's training range.
struct InadequacySample {
  std::vector<double> squared_error, expected;
  std::vector<std::vector<int>> beyond;  // per row, the joints beyond the fold's training range
};
// tau (m) of (3) over the rows with joint `joint` beyond the range (-1: the rows beyond on none); 0 without rows.
double EstimateInadequacy(const InadequacySample& sample, int joint);

// Summary of a held-out set: rows outside the support, and the fraction of 3-D errors within
// 3 sqrt(sd_pred^2 + sigma_3d^2) (the calibration check of (2)). sigma_3d = sqrt(3) sigma: the noise of a 3-D
// position (the trace of its covariance, like sd), so that sd_pred^2 + sigma_3d^2 is the expected squared
// 3-D error. `coverage_1d` uses sigma per residual instead (a stricter check, reported beside it).
// `sd`: the parameters' part (1), as PredictionSd returns it; the support rule applies to it, tau is added here.
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
