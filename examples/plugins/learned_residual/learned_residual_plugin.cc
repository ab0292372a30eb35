// The seed's learned compensation family as a kincal plugin: `learned_residual`, an estimator that runs
// after any other (a pipeline: `least_squares,learned_residual`) and adds to the robot it receives a
// kernel ridge regression of the position residual on the actual joint angles (kernel_ridge.h,
// residual_model.h). Hyper-parameters by 5-fold cross-validation on the rows it is given (a study's
// training rows only). Compensation needs no method of its own: the identified robot's forward kinematics
// includes the residual, so `jacobian` and `analytic_derivative` invert model plus residual.
//   kincal --plugin libkincal_learned_residual.so identify --method least_squares,learned_residual ...
#include <cmath>
#include <memory>
#include <string>

#include "estimators/estimator.h"
#include "framework/error.h"
#include "framework/plugin.h"
#include "residual_model.h"
#include "robot/joint_readings.h"
#include "robot/prediction.h"

namespace kincal_learned {
namespace {

class LearnedResidualEstimator final : public kincal::Estimator {
 public:
  LearnedResidualEstimator(const KernelRidgeOptions& options, bool in_tool_frame)
      : options_(options), in_tool_frame_(in_tool_frame) {}
  std::string name() const override { return "learned_residual"; }

 private:
  void DoEstimate(const kincal::Robot& start, const kincal::Robot& controller, const kincal::Dataset& data,
                  kincal::Robot* identified, kincal::EstimationReport* report) const override {
    const size_t n = data.rows.size();
    const auto previous = data.PreviousPoses();
    Eigen::MatrixXd X(n, start.dof()), Y(n, 3);
    for (size_t i = 0; i < n; ++i) {
      X.row(i) = kincal::ActualJointAngles(controller, start, data, i, previous).transpose();
      Eigen::Vector3d r = data.rows[i].p - kincal::PredictMarker(controller, start, data, i, previous);
      if (in_tool_frame_) r = start.model().ForwardKinematics(X.row(i).transpose()).linear().transpose() * r;
      Y.row(i) = r.transpose();
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

  KernelRidgeOptions options_;
  bool in_tool_frame_;
};

KernelRidgeOptions ReadOptions(const YAML::Node& node, bool* in_tool_frame) {
  KernelRidgeOptions o;
  kincal::OptionsReader reader(node, "learned_residual");
  std::string frame = "measurement";
  reader.Get("frame", &frame);
  if (frame != "measurement" && frame != "tool") reader.Fail("frame", "expected measurement or tool, got '" + frame + "'");
  *in_tool_frame = frame == "tool";
  reader.Get("ard_rounds", &o.ard_rounds);
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

}  // namespace
}  // namespace kincal_learned

KINCAL_PLUGIN(registrar) {
  registrar.AddEstimator(
      "learned_residual",
      "plugin: kernel ridge regression (Gaussian-process mean) of the position residual on the joint angles, "
      "on top of the robot it receives; hyper-parameters by cross-validation on the training rows",
      [](const YAML::Node& node) -> std::unique_ptr<kincal::Estimator> {
        bool in_tool_frame = false;
        const auto options = kincal_learned::ReadOptions(node, &in_tool_frame);
        return std::make_unique<kincal_learned::LearnedResidualEstimator>(options, in_tool_frame);
      });
}
