#include "estimators/geometric/geometric_estimator.h"

#include <cmath>
#include <stdexcept>

#include "estimators/geometric/geometric_solver.h"
#include "estimators/geometric/mdh_conversion.h"
#include "estimators/geometric/sweeps.h"
#include "estimators/geometric/uncertainty.h"

namespace kincal {

using geometric::ArcFit;

void ReadArcFitOptions(OptionsReader* reader, geometric::ArcFitOptions* arc) {
  std::string circle = geometric::ToString(arc->circle_fit);
  reader->Get("circle_fit", &circle);
  try {
    arc->circle_fit = geometric::ParseCircleFitMethod(circle);
  } catch (const std::invalid_argument& e) {
    reader->Fail("circle_fit", e.what());
  }
  reader->GetLength("min_spread", &arc->min_spread);
  reader->Get("min_curvature_ratio", &arc->min_curvature_ratio);
  reader->Get("max_iterations", &arc->max_iterations);
}

bool IsValidStddevMethod(const std::string& method, int bootstrap_samples, std::string* why) {
  if (method != "propagation" && method != "bootstrap" && method != "none") {
    if (why) *why = "stddev must be propagation, bootstrap or none, got '" + method + "'";
    return false;
  }
  if (method == "bootstrap" && bootstrap_samples < 10) {
    if (why) *why = "bootstrap_samples must be at least 10";
    return false;
  }
  return true;
}

bool GeometricEstimator::Options::IsValid(std::string* why) const {
  if (!arc.IsValid(why)) return false;
  if (!(parallel_threshold >= 0.0 && parallel_threshold < M_PI / 2)) {
    if (why) *why = "parallel_threshold must be in [0, 90) deg";
    return false;
  }
  return IsValidStddevMethod(stddev, bootstrap_samples, why);
}

GeometricEstimator::Options GeometricEstimator::Options::FromYaml(const YAML::Node& node) {
  OptionsReader reader(node, "geometric");
  Options o;
  ReadArcFitOptions(&reader, &o.arc);
  reader.GetAngleDeg("parallel_threshold", &o.parallel_threshold);
  reader.Get("marker", &o.marker);
  reader.Get("stddev", &o.stddev);
  reader.Get("bootstrap_samples", &o.bootstrap_samples);
  reader.Get("bootstrap_seed", &o.bootstrap_seed);
  reader.Finish();
  return o;
}

namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
constexpr double kDeg = 180.0 / M_PI;

std::vector<ArcFit> FitSweeps(const geometric::SweepSet& sweeps, const std::vector<int>& joints,
                              const geometric::ArcFitOptions& options, const std::string& who, const std::string& source) {
  std::vector<ArcFit> fits(sweeps.dof);
  for (int j : joints) {
    const geometric::Sweep& s = sweeps.sweeps[j - 1];
    try {
      fits[j - 1] = geometric::FitArc(s.points, s.x, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(who + ": " + sweeps.Where(j, source) + ": " + e.what());
    }
  }
  return fits;
}

}  // namespace

void GeometricEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                    EstimationReport* report) const {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("geometric: invalid options: " + why);
  const int n = start.dof();
  for (int i = 0; i < n; ++i) {
    if (start.model().joint_type(i) != JointType::kRevolute) {
      throw std::invalid_argument("geometric: joint " + std::to_string(i + 1) +
                                  " is prismatic; circle point analysis needs revolute joints");
    }
  }
  const Robot mdh_start = geometric::ToMdhRobot(start, "geometric");
  if (start.model().convention() != "mdh") {
    report->warnings.push_back("the start robot is " + start.model().convention() +
                               "; it was converted exactly to modified DH, which the identified robot uses");
  }
  const geometric::SweepSet sweeps = geometric::ExtractSweeps(controller, start, data, options_.marker, "geometric");
  std::vector<int> joints;
  for (int j = 1; j <= n; ++j) {
    if (!sweeps.Swept(j)) {
      throw std::invalid_argument("geometric: " + data.source + ": joint " + std::to_string(j) +
                                  " was never swept (no rows with sweep = " + std::to_string(j) +
                                  "); circle point analysis needs a sweep of every joint");
    }
    joints.push_back(j);
  }
  const std::vector<ArcFit> fits = FitSweeps(sweeps, joints, options_.arc, "geometric", data.source);
  const geometric::GeometricProblem problem =
      geometric::GeometricProblem::Make(mdh_start, sweeps, options_.parallel_threshold);
  const geometric::GeometricSolution solution = geometric::SolveGeometry(problem, fits);

  *identified = mdh_start;
  KinematicModel& model = identified->model();
  model.SetParameters(solution.parameters);
  if (sweeps.session != 0) {
    // The sweeps were measured in another session's frame: the base found is that session's.
    identified->session_bases[sweeps.session] = solution.T_meas_base;
    model.SetBase(mdh_start.model().base());
  }

  // Standard deviations.
  const auto& info = model.parameter_info();
  std::vector<bool> is_angle;
  for (const auto& p : info) is_angle.push_back(p.kind == ParameterInfo::Kind::kAngle);
  const geometric::ArcSolveFunction solve = [&](const std::vector<ArcFit>& f) {
    return geometric::SolveGeometry(problem, f).parameters;
  };
  geometric::Uncertainty u;
  if (options_.stddev == "propagation") {
    u = geometric::PropagateStopNoise(sweeps, joints, options_.arc, fits, is_angle, solve);
  } else if (options_.stddev == "bootstrap") {
    u = geometric::BootstrapStops(sweeps, joints, options_.arc, fits, is_angle, solve, options_.bootstrap_samples,
                                  static_cast<uint64_t>(options_.bootstrap_seed));
  } else {
    u.method = "none";
    u.stddev = Eigen::VectorXd::Constant(model.num_parameters(), NAN);
  }
  if (!u.note.empty()) report->warnings.push_back("standard deviations: " + u.note);

  // Parameters held by construction (geometric_solver.h).
  const std::string last = std::to_string(n);
  const auto held_note = [&](const std::string& name) -> std::string {
    if (name == "alpha_1" || name == "a_1" || name == "theta_1" || name == "d_1") {
      return "held at the start value: redundant with the base";
    }
    if (name == "d_" + last || name == "theta_" + last) return "held at the start value: redundant with the tool";
    if (name == "tool_roll" || name == "tool_pitch" || name == "tool_yaw") {
      return "held at the start value: a marker position does not show the tool's orientation";
    }
    if (sweeps.session != 0 && name.rfind("base_", 0) == 0) {
      return "held: the sweeps' session " + std::to_string(sweeps.session) + " has its own base (see details)";
    }
    return "";
  };
  const Eigen::VectorXd& start_values = mdh_start.model().Parameters();
  for (int k = 0; k < model.num_parameters(); ++k) {
    ParameterEstimate p;
    p.name = info[k].name;
    p.unit = info[k].kind == ParameterInfo::Kind::kAngle ? "rad" : "m";
    p.nominal = start_values[k];
    p.value = model.Parameters()[k];
    p.note = held_note(p.name);
    p.free = p.note.empty();
    p.stddev = p.free ? u.stddev[k] : NAN;
    if (!p.free) report->fixed_parameters.push_back(p.name);
    report->parameters.push_back(p);
  }

  // Details: the axes, the pairs, the noise.
  nlohmann::json axes = nlohmann::json::array();
  bool all_converged = true;
  for (int j = 1; j <= n; ++j) {
    const ArcFit& f = fits[j - 1];
    all_converged = all_converged && f.converged;
    report->iterations += f.iterations;
    nlohmann::json turned = nlohmann::json::array();
    for (const auto& [i, dx] : sweeps.sweeps[j - 1].moved) {
      turned.push_back({{"joint", i + 1}, {"angle_rad", fits[i].angle_slope * dx}});
    }
    axes.push_back({{"joint", j},
                    {"point_m", Vec(solution.axes[j - 1].point)},
                    {"direction", Vec(solution.axes[j - 1].direction)},
                    {"radius_m", f.radius},
                    {"stops", f.stops},
                    {"arc_deg", f.arc * kDeg},
                    {"plane_rms_m", f.axial_rms},
                    {"circle_rms_m", f.radial_rms},
                    {"angle_rms_m", f.tangential_rms},
                    {"angle_slope", f.angle_slope},
                    {"circle_fit_iterations", f.iterations},
                    {"circle_fit_converged", f.converged},
                    {"turned_back_about", turned}});
    if (!f.converged) {
      report->warnings.push_back("the circle fit of joint " + std::to_string(j) + " stopped at its iteration limit");
    }
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& pr : solution.frames.pairs) {
    pairs.push_back({{"joints", {pr.joint, pr.joint + 1}},
                     {"angle_deg", pr.angle * kDeg},
                     {"parallel", pr.parallel},
                     {"dropped_tilt_deg", pr.dropped_tilt * kDeg}});
    if (pr.parallel) {
      char text[400];
      std::snprintf(text, sizeof(text),
                    "axes %d and %d are parallel within %.4g deg (parallel_threshold %.4g deg): the common normal "
                    "follows the parallel-axes convention (d_%d held at its nominal value); MDH cannot hold the "
                    "%.4g deg tilt of axis %d about y_%d, which was dropped",
                    pr.joint, pr.joint + 1, pr.angle * kDeg, options_.parallel_threshold * kDeg, pr.joint,
                    std::abs(pr.dropped_tilt) * kDeg, pr.joint + 1, pr.joint);
      report->warnings.push_back(text);
    }
  }
  std::vector<int> order = sweeps.order;
  report->details = {
      {"circle_fit", geometric::ToString(options_.arc.circle_fit)},
      {"parallel_threshold_deg", options_.parallel_threshold * kDeg},
      {"sweep_order", order},
      {"marker", sweeps.marker},
      {"session", sweeps.session},
      {"calibration_configuration_rad", std::vector<double>(sweeps.q_cal.data(), sweeps.q_cal.data() + n)},
      {"calibration_joint_angles_rad", std::vector<double>(solution.q_cal.data(), solution.q_cal.data() + n)},
      {"calibration_row", sweeps.cal_row + 1},
      {"free_rows_ignored", sweeps.free_rows},
      {"marker_at_calibration_m", Vec(solution.p_meas_marker)},
      {"axes", axes},
      {"pairs", pairs},
      {"stddev", {{"method", u.method},
                  {"sigma_m", std::isfinite(u.sigma) ? nlohmann::json(u.sigma) : nlohmann::json(nullptr)},
                  {"degrees_of_freedom", u.degrees_of_freedom},
                  {"replicates", u.replicates},
                  {"note", u.note}}}};
  if (sweeps.session != 0) {
    const Eigen::Isometry3d& T = solution.T_meas_base;
    report->details["session_base"] = {{"session", sweeps.session}, {"xyz_m", Vec(T.translation())},
                                       {"rpy_rad", Vec(RpyFromRotation(T.linear()))}};
  }
  report->status = all_converged ? EstimationStatus::kConverged : EstimationStatus::kIterationLimit;
  report->message = "axes of " + std::to_string(n) + " sweeps (" + geometric::ToString(options_.arc.circle_fit) +
                    " circle fit), frames by common normals";
}

}  // namespace kincal
