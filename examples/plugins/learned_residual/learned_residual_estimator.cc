#include "learned_residual_estimator.h"

#include <cmath>
#include <memory>
#include <string>

#include "framework/registry.h"
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
  report->message = "kernel ridge regression of the position residual, length scales " + scales +
                    " rad, lambda " + std::to_string(residual->lambda());
  report->details["length_scales_rad"] = std::vector<double>(residual->length_scales().data(),
      residual->length_scales().data() + residual->length_scales().size());
  report->details["lambda"] = residual->lambda();
  report->details["cv_rms_m"] = residual->cv_rms();
  report->details["cv_rms_mean_only_m"] = residual->cv_rms_mean_only();
}

KernelRidgeOptions ReadLearnedResidualOptions(const YAML::Node& node, bool* in_tool_frame) {
  KernelRidgeOptions o;
  kincal::OptionsReader reader(node, "learned_residual");
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

