#include "framework/prediction.h"

#include <algorithm>
#include <cmath>

namespace kincal {

Eigen::VectorXd ActualJointAngles(const Robot& controller, const Robot& model, const Measurement& m) {
  if (!model.drives) return m.q;
  if (!m.encoders.empty()) {
    Eigen::VectorXd counts(static_cast<Eigen::Index>(m.encoders.size()));
    for (size_t i = 0; i < m.encoders.size(); ++i) counts[static_cast<Eigen::Index>(i)] = static_cast<double>(m.encoders[i]);
    return model.drives->AnglesFromCounts(counts);
  }
  if (!controller.drives) return m.q;
  return DriveModel::ActualFromCommanded(*controller.drives, *model.drives, m.q);
}

Eigen::Isometry3d PredictToolPose(const Robot& model, const Eigen::VectorXd& q_actual, int session) {
  const Eigen::Isometry3d T_meas_tool = model.model().ForwardKinematics(q_actual);
  if (session == 0 || !model.session_bases.count(session)) return T_meas_tool;
  return model.SessionBase(session) * model.model().base().inverse() * T_meas_tool;
}

Eigen::Vector3d PredictMarker(const Robot& controller, const Robot& model, const Measurement& m) {
  const Eigen::VectorXd q = ActualJointAngles(controller, model, m);
  return PredictToolPose(model, q, m.session) * model.MarkerPosition(m.marker);
}

ErrorStats Summarize(std::vector<double> errors) {
  ErrorStats s;
  s.count = static_cast<int>(errors.size());
  if (errors.empty()) return s;
  double sum = 0.0, sum2 = 0.0;
  for (double e : errors) {
    sum += e;
    sum2 += e * e;
    s.max = std::max(s.max, e);
  }
  s.mean = sum / s.count;
  s.rms = std::sqrt(sum2 / s.count);
  std::sort(errors.begin(), errors.end());
  s.median = s.count % 2 ? errors[s.count / 2] : 0.5 * (errors[s.count / 2 - 1] + errors[s.count / 2]);
  return s;
}

PredictionErrors EvaluatePredictions(const Robot& controller, const Robot& model, const Dataset& data) {
  PredictionErrors out;
  for (const Measurement& m : data.rows) {
    const Eigen::VectorXd q = ActualJointAngles(controller, model, m);
    const Eigen::Isometry3d T = PredictToolPose(model, q, m.session);
    out.position.push_back((T * model.MarkerPosition(m.marker) - m.p).norm());
    if (m.orientation) out.orientation.push_back(RotationAngleBetween(T.linear(), m.orientation->toRotationMatrix()));
  }
  out.position_stats = Summarize(out.position);
  out.orientation_stats = Summarize(out.orientation);
  return out;
}

}  // namespace kincal
