#include "learned_residual_estimator.h"

#include <cmath>
#include <memory>
#include <string>

#include "framework/registry.h"
#include "approach_residual.h"
#include "residual_model.h"
#include "robot/joint_readings.h"
#include "robot/prediction.h"

namespace kincal_learned {
namespace {

// The orientation of the robot's base frame in the frame of a session's measurements.
Eigen::Matrix3d SessionBaseRotation(const kincal::Robot& robot, int session) {
  if (session == 0 || !robot.session_bases.count(session)) return robot.model().base().linear();
  return robot.SessionBase(session).linear();
}

}  // namespace

void LearnedResidualEstimator::DoEstimate(const kincal::Robot& start, const kincal::Robot& controller,
                                          const kincal::Dataset& data, kincal::Robot* identified,
                                          kincal::EstimationReport* report) const {
  if (kincal::JointCorrectionOf(start)) {
    throw std::invalid_argument("learned_residual: the robot already has a learned residual");
  }
  if (with_approach_) return EstimateWithApproach(start, controller, data, identified, report);
  const size_t n = data.rows.size();
  const auto previous = data.PreviousPoses();
  Eigen::MatrixXd X(n, start.dof()), Y(n, 3);
  for (size_t i = 0; i < n; ++i) {
    X.row(i) = kincal::ActualJointAngles(controller, start, data, i, previous).transpose();
    // The residual in the robot's base frame (or its tool frame): the frame of the row's session moves
    // the model's whole pose (robot/prediction.h), so a residual in either frame moves with it.
    const Eigen::Vector3d r = data.rows[i].p - kincal::PredictMarker(controller, start, data, i, previous);
    const Eigen::Matrix3d R = in_tool_frame_
                                  ? kincal::PredictToolPose(start, X.row(i).transpose(), data.rows[i].session).linear()
                                  : SessionBaseRotation(start, data.rows[i].session);
    Y.row(i) = (R.transpose() * r).transpose();
  }
  auto residual = std::make_shared<KernelRidge>();
  residual->Fit(X, Y, options_);
  *identified = start.WithModel(std::make_unique<ResidualModel>(start.model().Clone(), residual, in_tool_frame_));
  report->status = kincal::EstimationStatus::kConverged;
  std::string scales;
  for (int j = 0; j < residual->length_scales().size(); ++j) {
    scales += (j ? " " : "") + std::to_string(residual->length_scales()[j]);
  }
  report->message = "kernel ridge regression of the position residual, length scales " + scales + " rad, lambda " +
                    std::to_string(residual->lambda());
  report->details["length_scales_rad"] = std::vector<double>(
      residual->length_scales().data(), residual->length_scales().data() + residual->length_scales().size());
  report->details["lambda"] = residual->lambda();
  report->details["cv_rms_m"] = residual->cv_rms();
  report->details["cv_rms_mean_only_m"] = residual->cv_rms_mean_only();
}

void LearnedResidualEstimator::EstimateWithApproach(const kincal::Robot& start, const kincal::Robot& controller,
                                                    const kincal::Dataset& data, kincal::Robot* identified,
                                                    kincal::EstimationReport* report) const {
  const size_t n = data.rows.size();
  const int dof = start.dof();
  const auto previous = data.PreviousPoses();
  Eigen::MatrixXd X(n, 2 * dof), Y(n, 3);
  Eigen::Vector3d p_tool_point = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const kincal::Measurement& m = data.rows[i];
    const Eigen::VectorXd qbar = kincal::DriveAngles(controller, start, m);
    const Eigen::VectorXd* q_prev = data.PreviousQ(previous[i]);
    const std::vector<int64_t>* enc_prev = data.PreviousEncoders(previous[i]);
    const Eigen::VectorXd qbar_prev =
        q_prev ? kincal::DriveAngles(controller, start, *q_prev, enc_prev ? *enc_prev : std::vector<int64_t>{})
               : Eigen::VectorXd();
    X.row(i) = ApproachFeatures(start, qbar, q_prev ? &qbar_prev : nullptr).transpose();
    const Eigen::Vector3d r = m.p - kincal::PredictMarker(controller, start, data, i, previous);
    Y.row(i) = (SessionBaseRotation(start, m.session).transpose() * r).transpose();
    // The reference point: the rows' marker (their mean with several).
    p_tool_point += start.MarkerPosition(m.marker) / static_cast<double>(n);
  }
  // The speeds in units of their spread over these rows, so that one grid of length scales fits both.
  Eigen::VectorXd spread = Eigen::VectorXd::Ones(2 * dof);
  for (int j = dof; j < 2 * dof; ++j) {
    const double mean = X.col(j).mean();
    const double sd = std::sqrt((X.col(j).array() - mean).square().mean());
    if (sd > 0) spread[j] = sd;
  }
  X = X * spread.cwiseInverse().asDiagonal();
  auto residual = std::make_shared<KernelRidge>();
  residual->Fit(X, Y, options_);
  auto approach = std::make_shared<ApproachResidual>(residual, spread, p_tool_point);
  *identified = start.WithModel(std::make_unique<ResidualModel>(start.model().Clone(), nullptr, false, approach));
  report->status = kincal::EstimationStatus::kConverged;
  std::string scales;
  for (int j = 0; j < residual->length_scales().size(); ++j) {
    scales += (j ? " " : "") + std::to_string(residual->length_scales()[j]);
  }
  report->message =
      "kernel ridge regression of the position residual on the readings and approach speeds, "
      "as a joint-level correction; length scales " +
      scales + " (rad, speed spreads), lambda " + std::to_string(residual->lambda());
  report->details["length_scales"] = std::vector<double>(
      residual->length_scales().data(), residual->length_scales().data() + residual->length_scales().size());
  report->details["speed_spreads"] = std::vector<double>(spread.data() + dof, spread.data() + 2 * dof);
  report->details["lambda"] = residual->lambda();
  report->details["cv_rms_m"] = residual->cv_rms();
  report->details["cv_rms_mean_only_m"] = residual->cv_rms_mean_only();
}

KernelRidgeOptions ReadLearnedResidualOptions(const YAML::Node& node, bool* in_tool_frame, bool* with_approach) {
  KernelRidgeOptions o;
  kincal::OptionsReader reader(node, "learned_residual");
  std::string features = "joints";
  reader.Get("features", &features);
  if (features != "joints" && features != "joints_and_approach") {
    reader.Fail("features", "expected joints or joints_and_approach, got '" + features + "'");
  }
  if (with_approach) *with_approach = features == "joints_and_approach";
  std::string frame = "base";
  reader.Get("frame", &frame);
  if (frame != "base" && frame != "tool") reader.Fail("frame", "expected base or tool, got '" + frame + "'");
  *in_tool_frame = frame == "tool";
  reader.Get("ard_rounds", &o.ard_rounds);
  std::string kernel = "squared_exponential";
  reader.Get("kernel", &kernel);
  if (kernel != "squared_exponential" && kernel != "matern52") {
    reader.Fail("kernel", "expected squared_exponential or matern52, got '" + kernel + "'");
  }
  o.kernel = kernel == "matern52" ? Kernel::kMatern52 : Kernel::kSquaredExponential;
  reader.Get("folds", &o.folds);
  int seed = static_cast<int>(o.seed);
  reader.Get("seed", &seed);
  o.seed = static_cast<uint64_t>(seed);
  if (node && node.IsMap() && node["length_scales"]) o.length_scales = node["length_scales"].as<std::vector<double>>();
  if (node && node.IsMap() && node["lambdas"]) o.lambdas = node["lambdas"].as<std::vector<double>>();
  std::vector<std::string> ignored;
  reader.Get("length_scales", &ignored);
  reader.Get("lambdas", &ignored);
  reader.Finish();
  bool ok = o.folds >= 2 && o.ard_rounds >= 0 && !o.length_scales.empty() && !o.lambdas.empty();
  for (double l : o.length_scales) ok = ok && l > 0 && std::isfinite(l);
  for (double l : o.lambdas) ok = ok && l > 0 && std::isfinite(l);
  if (!ok) throw std::invalid_argument("learned_residual: folds >= 2 and positive length_scales (rad) and lambdas");
  return o;
}

}  // namespace kincal_learned
