#include "estimators/geometric/geometric_solver.h"

#include <stdexcept>

#include "framework/math.h"

namespace kincal::geometric {
namespace {

// Rotation by `angle` about the line `axis` (a screw without pitch).
Eigen::Isometry3d TurnAbout(const AxisLine& axis, double angle) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(axis.point);
  T.rotate(Eigen::AngleAxisd(angle, axis.direction));
  T.translate(-axis.point);
  return T;
}

// Actual angle per unit of joint i's drive variable.
double Slope(const GeometricProblem& problem, const std::vector<ArcFit>& fits, int i) {
  return problem.angles_from_readings ? 1.0 : fits[i].angle_slope;
}

std::string Row(const char* key, int i) { return std::string(key) + "_" + std::to_string(i); }

}  // namespace

GeometricProblem GeometricProblem::Make(const Robot& mdh_start, const SweepSet& sweeps, double parallel_threshold) {
  const KinematicModel& model = mdh_start.model();
  const bool hayati = model.convention() == "hayati";
  if (model.convention() != "mdh" && !hayati) {
    throw std::logic_error("GeometricProblem: the start robot must be MDH or Hayati");
  }
  const int n = model.dof();
  GeometricProblem p;
  p.start = mdh_start;
  p.x_cal = sweeps.x_cal;
  p.parallel_threshold = parallel_threshold;
  p.keep_tilt = hayati;
  for (int i = 1; i <= n; ++i) {
    p.moved.push_back(sweeps.sweeps[i - 1].moved);
    p.nominal.push_back({model.Parameter(Row("alpha", i)), model.Parameter(Row("a", i)),
                         model.Parameter(Row("theta", i)), model.Parameter(Row("d", i)),
                         hayati ? model.Parameter(Row("beta", i)) : 0.0});
  }
  p.x1_hint = model.FramePoses(sweeps.x_cal)[1].linear().col(0);
  p.p_tool_marker = mdh_start.MarkerPosition(sweeps.marker);
  p.markers = static_cast<int>(sweeps.markers.size());
  return p;
}

GeometricSolution SolveGeometry(const GeometricProblem& problem, const std::vector<ArcFit>& fits) {
  const int n = problem.start.dof();
  if (static_cast<int>(fits.size()) != n) throw std::logic_error("SolveGeometry: one arc fit per joint expected");
  GeometricSolution sol;

  // Axes at the calibration configuration, proximal first (a joint's correction uses the axes before it).
  for (int j = 1; j <= n; ++j) {
    const ArcFit& fit = fits[j - 1];
    AxisLine axis{fit.center, fit.axis};
    Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
    for (const auto& [i, displacement] : problem.moved[j - 1]) {
      moved = moved * TurnAbout(sol.axes[i], Slope(problem, fits, i) * displacement);
    }
    const Eigen::Isometry3d back = moved.inverse();
    axis.point = back * axis.point;
    axis.direction = back.linear() * axis.direction;
    sol.axes.push_back(axis);
    if (j == n) {
      // The markers with joint n at its calibration angle, measured on joint n's arcs.
      for (int m = 0; m < static_cast<int>(fit.circles.size()); ++m) {
        sol.p_meas_markers.push_back(back * fit.MarkerAt(m, problem.x_cal[n - 1]));
      }
      sol.p_meas_marker = sol.p_meas_markers.at(0);
    }
  }

  // The actual joint angles of the calibration configuration, measured on each joint's arc.
  sol.q_cal.resize(n);
  for (int i = 0; i < n; ++i) sol.q_cal[i] = Slope(problem, fits, i) * problem.x_cal[i];
  sol.frames = FramesFromAxes(sol.axes, problem.nominal, sol.q_cal, problem.x1_hint, problem.parallel_threshold,
                              problem.keep_tilt);
  const std::vector<Eigen::Isometry3d>& F = sol.frames.frames;

  sol.rows.resize(n);
  sol.rows[0] = problem.nominal[0];
  sol.T_meas_base = F[0] * MdhTransform(sol.rows[0], sol.q_cal[0]).inverse();
  for (int i = 2; i <= n; ++i) {
    MdhRow row = problem.keep_tilt && sol.frames.pairs[i - 2].parallel
                     ? HayatiRowFromFrames(F[i - 2], F[i - 1], sol.q_cal[i - 1])
                     : MdhRowFromFrames(F[i - 2], F[i - 1], sol.q_cal[i - 1]);
    // Report theta on the nominal's side of the circle (90.4 deg, not -269.6).
    row.theta = problem.nominal[i - 1].theta + WrapAngle(row.theta - problem.nominal[i - 1].theta);
    sol.rows[i - 1] = row;
  }
  // Held by construction; set exactly rather than to within rounding.
  sol.rows[n - 1].d = problem.nominal[n - 1].d;
  sol.rows[n - 1].theta = problem.nominal[n - 1].theta;

  std::unique_ptr<KinematicModel> model = problem.start.model().Clone();
  Eigen::VectorXd v = model->Parameters();
  for (int i = 1; i <= n; ++i) {
    v[model->ParameterIndex(Row("alpha", i))] = sol.rows[i - 1].alpha;
    v[model->ParameterIndex(Row("a", i))] = sol.rows[i - 1].a;
    v[model->ParameterIndex(Row("theta", i))] = sol.rows[i - 1].theta;
    v[model->ParameterIndex(Row("d", i))] = sol.rows[i - 1].d;
    if (problem.keep_tilt) v[model->ParameterIndex(Row("beta", i))] = sol.rows[i - 1].beta;
  }
  model->SetParameters(v);
  model->SetBase(sol.T_meas_base);
  // Tool: the marker's measured position in frame n of the model just built (so the model reproduces it
  // exactly at the calibration configuration), keeping the start robot's tool orientation.
  const Eigen::Isometry3d T_meas_n = model->FramePoses(sol.q_cal)[n];
  Eigen::Isometry3d T_n_tool = model->tool();
  if (problem.markers > 1) {
    // The markers' positions in the start tool frame, each reproduced exactly at the calibration configuration.
    const Eigen::Isometry3d T_tool_meas = (T_meas_n * T_n_tool).inverse();
    for (const Eigen::Vector3d& p : sol.p_meas_markers) sol.p_tool_markers.push_back(T_tool_meas * p);
  } else {
    T_n_tool.translation() = T_meas_n.inverse() * sol.p_meas_marker - T_n_tool.linear() * problem.p_tool_marker;
  }
  model->SetTool(T_n_tool);
  sol.parameters = model->Parameters();
  return sol;
}

}  // namespace kincal::geometric
