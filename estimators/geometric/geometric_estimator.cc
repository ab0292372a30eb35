#include "estimators/geometric/geometric_estimator.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include "estimators/geometric/axis_fit.h"
#include "estimators/geometric/geometric_solver.h"
#include "estimators/geometric/sweeps.h"
#include "estimators/geometric/uncertainty.h"
#include "framework/error.h"
#include "models/conversion.h"
#include "robot/prediction.h"

namespace kincal {

using geometric::ArcFit;

std::string StddevRule(const std::string& method, int bootstrap_samples) {
  std::string why;
  return IsValidStddevMethod(method, bootstrap_samples, &why) ? std::string() : why;
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

const OptionTable<geometric::UncertaintyOptions>& geometric::UncertaintyOptions::Table() {
  using O = geometric::UncertaintyOptions;
  static const OptionTable<O> table =
      OptionTable<O>("stop uncertainty")
          .Add("stddev", &O::stddev, "propagation, bootstrap or none", OneOf({"propagation", "bootstrap", "none"}))
          .Add("bootstrap_samples", &O::bootstrap_samples, "resamples of the bootstrap (at least 10)")
          .Add("bootstrap_seed", &O::bootstrap_seed, "seed of the bootstrap's random stream")
          .Rule({"bootstrap_samples", "stddev"}, [](const O& o) { return StddevRule(o.stddev, o.bootstrap_samples); });
  return table;
}

const OptionTable<GeometricEstimator::Options>& GeometricEstimator::Options::Table() {
  using O = GeometricEstimator::Options;
  static const OptionTable<O> table =
      OptionTable<O>("geometric")
          .Include(geometric::ArcFitOptions::Table(), &O::arc)
          .Add("parallel_threshold", OptionUnit::kAngleDeg, &O::parallel_threshold,
               "consecutive axes closer to parallel than this are parallel", Between(0, 90, false, true))
          .Add("marker", &O::marker, "the marker whose sweeps to use; empty: every marker")
          .Add("joint_angles", &O::joint_angles, "auto, arcs or readings", OneOf({"auto", "arcs", "readings"}))
          .Add("markers_from", &O::markers_from, "auto, stops or arc", OneOf({"auto", "stops", "arc"}))
          .Include(geometric::UncertaintyOptions::Table());
  return table;
}

bool GeometricEstimator::Options::IsValid(std::string* why) const { return Table().Validate(*this, why); }

GeometricEstimator::Options GeometricEstimator::Options::FromYaml(const YAML::Node& node) { return Table().Read(node); }

namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
constexpr double kDeg = 180.0 / M_PI;

std::vector<ArcFit> FitSweeps(const geometric::SweepSet& sweeps, const std::vector<int>& joints,
                              const geometric::ArcFitOptions& options, const std::string& who,
                              const std::string& source) {
  std::vector<ArcFit> fits(sweeps.dof);
  for (int j : joints) {
    const geometric::Sweep& s = sweeps.sweeps[j - 1];
    try {
      fits[j - 1] = geometric::FitAxis(s.marker_points, s.x, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(who + ": " + sweeps.Where(j, source) + ": " + e.what());
    }
  }
  return fits;
}

// Every marker's position in the tool frame that best reproduces all its sweep stops with the identified
// chain: T_meas_tool(q_r) m = p_r for each of its rows, whose least-squares solution is the mean of
// T_meas_tool(q_r)^-1 p_r (a rigid transform keeps distances).
void MarkersFromStops(const Robot& controller, const Dataset& data, const std::vector<std::string>& markers,
                      Robot* identified) {
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::map<std::string, std::pair<Eigen::Vector3d, int>> sums;
  for (const std::string& id : markers) sums[id] = {Eigen::Vector3d::Zero(), 0};
  for (size_t r = 0; r < data.rows.size(); ++r) {
    const Measurement& m = data.rows[r];
    if (m.sweep <= 0 || !sums.count(m.marker)) continue;
    const Eigen::VectorXd q = ActualJointAngles(controller, *identified, data, r, previous);
    auto& [sum, count] = sums[m.marker];
    sum += PredictToolPose(*identified, q, m.session).inverse() * m.p;
    ++count;
  }
  for (const auto& [id, sum_count] : sums) identified->markers[id] = sum_count.first / sum_count.second;
}

}  // namespace

namespace {

// The start robot in a convention the construction builds: modified DH (models/conversion.h: exact for
// every convention a robot file can have), or Hayati's as it is, whose beta keeps the tilt of a nearly
// parallel axis that MDH would drop. Revolute joints only.
Robot ConstructionStart(const Robot& start) {
  for (int i = 0; i < start.dof(); ++i) {
    if (start.model().joint_type(i) != JointType::kRevolute) {
      throw std::invalid_argument("geometric: joint " + std::to_string(i + 1) +
                                  " is prismatic; circle point analysis needs revolute joints");
    }
  }
  if (start.model().convention() == "mdh" || start.model().convention() == "hayati") return start;
  return start.WithModel(ConvertModel(start.model(), "mdh"));
}

std::vector<int> SweptJoints(const geometric::SweepSet& sweeps, int n, const Dataset& data) {
  std::vector<int> joints;
  for (int j = 1; j <= n; ++j) {
    if (!sweeps.Swept(j)) {
      throw std::invalid_argument("geometric: " + data.source + ": joint " + std::to_string(j) +
                                  " was never swept (no rows with sweep = " + std::to_string(j) +
                                  "); circle point analysis needs a sweep of every joint");
    }
    joints.push_back(j);
  }
  return joints;
}

geometric::Uncertainty StandardDeviations(const GeometricEstimator::Options& options, const geometric::SweepSet& sweeps,
                                          const std::vector<int>& joints, const std::vector<ArcFit>& fits,
                                          const geometric::GeometricProblem& problem, const KinematicModel& model) {
  std::vector<bool> is_angle;
  for (const auto& p : model.parameter_info()) is_angle.push_back(p.kind == ParameterInfo::Kind::kAngle);
  const geometric::ArcSolveFunction solve = [&](const std::vector<ArcFit>& f) {
    return geometric::SolveGeometry(problem, f).parameters;
  };
  return geometric::StopUncertainty(options.stddev, sweeps, joints, options.arc, fits, is_angle, solve,
                                    options.bootstrap_samples, static_cast<uint64_t>(options.bootstrap_seed));
}

// Every MDH parameter with its standard deviation, those held by construction (geometric_solver.h) noted.
void ReportParameters(const Robot& construction_start, const KinematicModel& model, const geometric::Uncertainty& u,
                      const geometric::SweepSet& sweeps, const std::vector<geometric::JointPair>& pairs,
                      EstimationReport* report) {
  const bool several = sweeps.markers.size() > 1;
  const std::string last = std::to_string(model.dof());
  const auto held_note = [&](const std::string& name) -> std::string {
    if (name == "alpha_1" || name == "a_1" || name == "theta_1" || name == "d_1" || name == "beta_1") {
      return "held at the start value: redundant with the base";
    }
    // Hayati's beta_i is free where axes i-1 and i are parallel (pair i-2): elsewhere the common normal
    // makes it zero (it would duplicate d and theta of the row before).
    if (name.rfind("beta_", 0) == 0 && !pairs.at(std::stoul(name.substr(5)) - 2).parallel) {
      return "zero by construction: axes " + std::to_string(std::stoi(name.substr(5)) - 1) + " and " +
             name.substr(5) + " are not parallel";
    }
    if (name == "d_" + last || name == "theta_" + last) return "held at the start value: redundant with the tool";
    if (several && (name == "tool_x" || name == "tool_y" || name == "tool_z")) {
      return "held at the start value: the markers' positions (details) are identified instead";
    }
    if (name == "tool_roll" || name == "tool_pitch" || name == "tool_yaw") {
      return "held at the start value: a marker position does not show the tool's orientation";
    }
    if (sweeps.session != 0 && name.rfind("base_", 0) == 0) {
      return "held: the sweeps' session " + std::to_string(sweeps.session) + " has its own base (see details)";
    }
    return "";
  };
  const auto& info = model.parameter_info();
  const Eigen::VectorXd& start_values = construction_start.model().Parameters();
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
}

// Details of each fitted axis; a warning for each circle fit stopped at its limit. Adds the fits'
// iterations to the report's; returns whether every fit converged.
bool ReportAxes(const geometric::SweepSet& sweeps, const std::vector<ArcFit>& fits,
                const geometric::GeometricProblem& problem, const geometric::GeometricSolution& solution,
                EstimationReport* report, nlohmann::json* axes) {
  const bool several = sweeps.markers.size() > 1;
  bool all_converged = true;
  *axes = nlohmann::json::array();
  for (int j = 1; j <= static_cast<int>(fits.size()); ++j) {
    const ArcFit& f = fits[j - 1];
    all_converged = all_converged && f.converged;
    report->iterations += f.iterations;
    nlohmann::json turned = nlohmann::json::array();
    for (const auto& [i, dx] : sweeps.sweeps[j - 1].moved) {
      turned.push_back(
          {{"joint", i + 1}, {"angle_rad", (problem.angles_from_readings ? 1.0 : fits[i].angle_slope) * dx}});
    }
    nlohmann::json circles = nlohmann::json::array();
    for (size_t m = 0; m < f.circles.size() && several; ++m) {
      circles.push_back(
          {{"marker", sweeps.markers[m]}, {"center_m", Vec(f.circles[m].center)}, {"radius_m", f.circles[m].radius}});
    }
    axes->push_back({{"joint", j},
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
    if (several) axes->back()["marker_circles"] = circles;
    if (!f.converged) {
      report->warnings.push_back("the circle fit of joint " + std::to_string(j) + " stopped at its iteration limit");
    }
  }
  return all_converged;
}

// Details of each pair of consecutive axes; a warning for each parallel pair whose tilt MDH dropped.
nlohmann::json ReportPairs(const geometric::GeometricSolution& solution, double parallel_threshold, bool keep_tilt,
                           EstimationReport* report) {
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& pr : solution.frames.pairs) {
    pairs.push_back({{"joints", {pr.joint, pr.joint + 1}},
                     {"angle_deg", pr.angle * kDeg},
                     {"parallel", pr.parallel},
                     {"dropped_tilt_deg", pr.dropped_tilt * kDeg},
                     {"kept_tilt_deg", pr.kept_tilt * kDeg}});
    if (pr.parallel && !keep_tilt) {
      char text[400];
      std::snprintf(text, sizeof(text),
                    "axes %d and %d are parallel within %.4g deg (parallel_threshold %.4g deg): the common normal "
                    "follows the parallel-axes convention (d_%d held at its nominal value); MDH cannot hold the "
                    "%.4g deg tilt of axis %d about y_%d, which was dropped",
                    pr.joint, pr.joint + 1, pr.angle * kDeg, parallel_threshold * kDeg, pr.joint,
                    std::abs(pr.dropped_tilt) * kDeg, pr.joint + 1, pr.joint);
      report->warnings.push_back(text);
    }
  }
  return pairs;
}

// The markers' positions in the tool (several markers) and the sweeps' session base (another session's
// frame), in the report's details.
void AddMarkerAndSessionDetails(const geometric::SweepSet& sweeps, const geometric::GeometricSolution& solution,
                                const Robot& identified, EstimationReport* report) {
  const bool several = sweeps.markers.size() > 1;
  if (several) {
    nlohmann::json positions = nlohmann::json::object();
    nlohmann::json from_arc = nlohmann::json::object();
    for (size_t m = 0; m < sweeps.markers.size(); ++m) {
      positions[sweeps.markers[m]] = Vec(identified.markers.at(sweeps.markers[m]));
      from_arc[sweeps.markers[m]] = Vec(solution.p_tool_markers[m]);
    }
    report->details["markers_in_tool_m"] = positions;
    report->details["markers_in_tool_from_last_arc_m"] = from_arc;
  }
  if (sweeps.session != 0) {
    const Eigen::Isometry3d& T = solution.T_meas_base;
    report->details["session_base"] = {
        {"session", sweeps.session}, {"xyz_m", Vec(T.translation())}, {"rpy_rad", Vec(RpyFromRotation(T.linear()))}};
  }
}

}  // namespace

void GeometricEstimator::CheckStart(const Robot& start) const {
  const Robot built = ConstructionStart(start);
  if (built.model().convention() != start.model().convention()) {
    ConvertModel(built.model(), start.model().convention());
  }
}

void GeometricEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                                    EstimationReport* report) const {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("geometric: invalid options: " + OneLine(why));
  data.RequireFullPoints("geometric (circle fits)");
  const int n = start.dof();
  const Robot construction_start = ConstructionStart(start);
  const geometric::SweepSet sweeps = geometric::ExtractSweeps(controller, start, data, options_.marker, "geometric",
                                                              /*several_markers=*/true);
  const bool several = sweeps.markers.size() > 1;
  const std::vector<int> joints = SweptJoints(sweeps, n, data);
  const std::vector<ArcFit> fits = FitSweeps(sweeps, joints, options_.arc, "geometric", data.source);
  geometric::GeometricProblem problem =
      geometric::GeometricProblem::Make(construction_start, sweeps, options_.parallel_threshold);
  problem.angles_from_readings =
      options_.joint_angles == "readings" || (options_.joint_angles == "auto" && !start.drives.has_value());
  const bool markers_from_stops = several && (options_.markers_from == "stops" ||
                                              (options_.markers_from == "auto" && problem.angles_from_readings));
  const geometric::GeometricSolution solution = geometric::SolveGeometry(problem, fits);

  *identified = construction_start;
  KinematicModel& model = identified->model();
  model.SetParameters(solution.parameters);
  if (several) {
    for (size_t m = 0; m < sweeps.markers.size(); ++m)
      identified->markers[sweeps.markers[m]] = solution.p_tool_markers[m];
    if (markers_from_stops) MarkersFromStops(controller, data, sweeps.markers, identified);
  }
  if (sweeps.session != 0) {
    // The sweeps were measured in another session's frame: the base found is that session's.
    identified->session_bases[sweeps.session] = solution.T_meas_base;
    model.SetBase(construction_start.model().base());
  }

  const geometric::Uncertainty u = StandardDeviations(options_, sweeps, joints, fits, problem, model);
  if (!u.note.empty()) report->warnings.push_back("standard deviations: " + u.note);
  ReportParameters(construction_start, model, u, sweeps, solution.frames.pairs, report);
  nlohmann::json axes;
  const bool all_converged = ReportAxes(sweeps, fits, problem, solution, report, &axes);
  const nlohmann::json pairs = ReportPairs(solution, options_.parallel_threshold, problem.keep_tilt, report);
  std::vector<int> order = sweeps.order;
  report->details = {
      {"circle_fit", geometric::ToString(options_.arc.circle_fit)},
      {"parallel_threshold_deg", options_.parallel_threshold * kDeg},
      {"sweep_order", order},
      {"marker", sweeps.marker},
      {"markers", sweeps.markers},
      {"joint_angles", problem.angles_from_readings ? "readings" : "arcs"},
      {"markers_from", markers_from_stops ? "stops" : "arc"},
      {"session", sweeps.session},
      {"calibration_configuration_rad", std::vector<double>(sweeps.q_cal.data(), sweeps.q_cal.data() + n)},
      {"calibration_joint_angles_rad", std::vector<double>(solution.q_cal.data(), solution.q_cal.data() + n)},
      {"calibration_row", sweeps.cal_row + 1},
      {"free_rows_ignored", sweeps.free_rows},
      {"marker_at_calibration_m", Vec(solution.p_meas_marker)},
      {"axes", axes},
      {"pairs", pairs},
      {"stddev", u.ToJson()}};
  AddMarkerAndSessionDetails(sweeps, solution, *identified, report);
  if (start.model().convention() != construction_start.model().convention()) {
    // Back to the start's convention, exactly (models/conversion.h); the parameters listed are the
    // construction's modified DH ones.
    *identified = identified->WithModel(ConvertModel(identified->model(), start.model().convention()));
    report->warnings.push_back("the start robot is " + start.model().convention() +
                               ": the geometry was built in modified DH (the parameters listed) and converted "
                               "exactly back to " +
                               start.model().convention());
  }
  report->status = all_converged ? EstimationStatus::kConverged : EstimationStatus::kIterationLimit;
  report->message = "axes of " + std::to_string(n) + " sweeps" +
                    (several ? " of " + std::to_string(sweeps.markers.size()) + " markers jointly" : std::string()) +
                    " (" + geometric::ToString(options_.arc.circle_fit) + " circle fit), frames by common normals";
}

}  // namespace kincal
