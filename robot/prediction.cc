#include "robot/prediction.h"

#include <algorithm>
#include <cmath>

#include "framework/error.h"

namespace kincal {

Eigen::Isometry3d PredictToolPose(const Robot& model, const Eigen::VectorXd& q_actual, int session) {
  const Eigen::Isometry3d T_meas_tool = model.model().ForwardKinematics(q_actual);
  if (session == 0 || !model.session_bases.count(session)) return T_meas_tool;
  return model.SessionBase(session) * model.model().base().inverse() * T_meas_tool;
}

Eigen::Vector3d PredictMarker(const Robot& controller, const Robot& model, const Dataset& data, size_t row,
                              const std::vector<Dataset::Previous>& previous) {
  const Measurement& m = data.rows[row];
  const Eigen::VectorXd q = ActualJointAngles(controller, model, data, row, previous);
  return PredictToolPose(model, q, m.session) * model.MarkerPosition(m.marker);
}

std::vector<Eigen::Vector3d> PredictMarkers(const Robot& controller, const Robot& model, const Dataset& data) {
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::vector<Eigen::Vector3d> out;
  out.reserve(data.rows.size());
  for (size_t i = 0; i < data.rows.size(); ++i) out.push_back(PredictMarker(controller, model, data, i, previous));
  return out;
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

Eigen::VectorXd RowResidual(const Robot& model, const Dataset& data, size_t row, const Eigen::Vector3d& predicted) {
  const Measurement& m = data.rows[row];
  if (m.kind == MeasurementKind::kPoint) {
    Eigen::VectorXd r(m.axes[0] + m.axes[1] + m.axes[2]);
    int k = 0;
    for (int a = 0; a < 3; ++a)
      if (m.axes[a]) r[k++] = predicted[a] - m.p[a];
    return r;
  }
  const Fixture::Type type = FixtureTypeOf(m.kind);
  const Fixture* f = model.fixtures.Find(type, m.fixture);
  if (!f) {
    ThrowInputError(data.source, m.line, 0,
                    "row " + std::to_string(row + 1) + " names " + FixtureTypeName(type) + " '" + m.fixture +
                        "', which the robot's fixtures do not give");
  }
  // Fixtures are given in the frame of session 0.
  const Eigen::Vector3d p =
      m.session == 0 ? predicted : Eigen::Vector3d(model.SessionBase(0) * (model.SessionBase(m.session).inverse() * predicted));
  switch (m.kind) {
    case MeasurementKind::kDistance:
      return Eigen::VectorXd::Constant(1, (p - f->position).norm() - m.distance);
    case MeasurementKind::kPlane:
      return Eigen::VectorXd::Constant(1, f->normal.dot(p) - f->offset);
    default:
      return p - f->position;
  }
}

PredictionErrors EvaluatePredictions(const Robot& controller, const Robot& model, const Dataset& data) {
  PredictionErrors out;
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    const Eigen::VectorXd q = ActualJointAngles(controller, model, data, i, previous);
    const Eigen::Isometry3d T = PredictToolPose(model, q, m.session);
    out.position.push_back(RowResidual(model, data, i, T * model.MarkerPosition(m.marker)).norm());
    if (m.orientation) out.orientation.push_back(RotationAngleBetween(T.linear(), m.orientation->toRotationMatrix()));
  }
  out.position_stats = Summarize(out.position);
  out.orientation_stats = Summarize(out.orientation);
  return out;
}

}  // namespace kincal
