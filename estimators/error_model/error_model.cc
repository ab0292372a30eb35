#include "estimators/error_model/error_model.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Cholesky>

#include "estimators/error_model/start_placement.h"

namespace kincal {
namespace {

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

namespace {

// Builds the problem with every structurally free parameter from prep->start, analyses identifiability
// at its start and holds what the data cannot determine.
void AnalyzeAndHold(const Robot& controller, const Dataset& data, const ErrorModelOptions& options,
                    const RowWeighting& weighting, PreparedErrorModel* prep) {
  const ErrorModelProblem structural(prep->start, controller, data, options);
  const NormalEquations ne = AccumulateNormalEquations(structural, structural.InitialX(), weighting);
  prep->identifiability = AnalyzeIdentifiability(structural, ne.JtJ, ne.num_rows, options.identifiability_tolerance);
  const IdentifiabilityAnalysis& a = prep->identifiability;
  ErrorModelProblem held = structural;
  for (size_t k = 0; k < a.unidentifiable.size(); ++k) {
    // Hold one at a time, each with its reason: indices refer to `structural`, so map each by name.
    const auto names = held.ParameterNames();
    const int index = static_cast<int>(std::find(names.begin(), names.end(), a.unidentifiable_names[k]) - names.begin());
    held = held.Hold({index}, a.reasons[k], true);
  }
  prep->problem = std::make_unique<ErrorModelProblem>(held);
  // The normal equations at the start, restricted to the identifiable columns (same x, same rows): the
  // held problem lists the structural problem's parameters in the same order, minus the held ones.
  NormalEquations& initial = prep->initial;
  initial = ne;
  const std::vector<int>& keep = a.identifiable;
  const int p = static_cast<int>(keep.size());
  initial.JtJ.resize(p, p);
  initial.Jtr.resize(p);
  for (int i = 0; i < p; ++i) {
    initial.Jtr[i] = ne.Jtr[keep[i]];
    for (int j = 0; j < p; ++j) initial.JtJ(i, j) = ne.JtJ(keep[i], keep[j]);
  }
}

}  // namespace

PreparedErrorModel PrepareErrorModel(const Robot& start, const Robot& controller, const Dataset& data,
                                     const ErrorModelOptions& options, const RowWeighting& weighting) {
  PreparedErrorModel prep;
  prep.input = start;
  // A reflector the data name but the robot file does not declare starts at the tool origin, to be
  // placed below, when the options let markers be identified.
  for (const Measurement& m : data.rows) {
    if (m.marker.empty() || start.markers.count(m.marker) || !options.identify_markers) continue;
    bool held = false;
    for (const auto& name : options.fixed) held = held || name == "markers" || name.rfind("marker_" + m.marker + "_", 0) == 0;
    if (!held) prep.input.markers[m.marker] = Eigen::Vector3d::Zero();
  }
  prep.start = prep.input;
  // Validates everything (throws) before the registration runs on the data.
  { const ErrorModelProblem check(prep.input, controller, data, options); }
  const StartPlacement placement = PlaceStart(controller, data, options, &prep.start);
  prep.warnings = placement.warnings;
  prep.placed = placement.placed;
  AnalyzeAndHold(controller, data, options, weighting, &prep);
  prep.registered_rms = prep.initial.PositionRms();
  return prep;
}

bool ReanalyzeIdentifiability(const Eigen::VectorXd& solution, const RowWeighting& weighting,
                              PreparedErrorModel* prep, Eigen::VectorXd* x) {
  const ErrorModelProblem& old = *prep->problem;
  Robot at_solution;
  old.WriteToRobot(solution, &at_solution);
  PreparedErrorModel next;
  next.input = prep->input;
  next.start = at_solution;
  next.warnings = prep->warnings;
  next.placed = prep->placed;
  next.registered_rms = prep->registered_rms;
  AnalyzeAndHold(old.controller(), old.data(), old.options(), weighting, &next);
  if (next.identifiability.unidentifiable_names == prep->identifiability.unidentifiable_names) {
    *x = solution;
    return false;
  }
  std::string freed, held;
  for (const auto& name : prep->identifiability.unidentifiable_names) {
    const auto& now = next.identifiability.unidentifiable_names;
    if (std::find(now.begin(), now.end(), name) == now.end()) freed += " " + name;
  }
  for (const auto& name : next.identifiability.unidentifiable_names) {
    const auto& before = prep->identifiability.unidentifiable_names;
    if (std::find(before.begin(), before.end(), name) == before.end()) held += " " + name;
  }
  next.warnings.push_back("identifiability re-analysed at the first solution:" +
                          (freed.empty() ? std::string() : " freed" + freed) + (held.empty() ? "" : ", held" + held));
  *prep = std::move(next);
  *x = prep->problem->InitialX();
  return true;
}

Covariance ComputeCovariance(const NormalEquations& ne, int p) {
  Covariance c;
  c.degrees_of_freedom = ne.num_residuals - p;
  c.sigma = c.degrees_of_freedom > 0 ? std::sqrt(ne.irls_squares / c.degrees_of_freedom) : NAN;
  c.matrix = Eigen::MatrixXd::Constant(p, p, NAN);
  c.stddev = Eigen::VectorXd::Constant(p, NAN);
  if (p == 0) return c;
  // Invert in the column-normalised basis, where J^T W J is best conditioned.
  const Eigen::VectorXd d = ne.JtJ.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!(d.minCoeff() > 0.0)) return c;
  const Eigen::VectorXd d_inv = d.cwiseInverse();
  const Eigen::MatrixXd S = d_inv.asDiagonal() * ne.JtJ * d_inv.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return c;
  const Eigen::MatrixXd S_inv = llt.solve(Eigen::MatrixXd::Identity(p, p));
  c.matrix = c.sigma * c.sigma * (d_inv.asDiagonal() * S_inv * d_inv.asDiagonal());
  c.stddev = c.matrix.diagonal().cwiseMax(0.0).cwiseSqrt();
  return c;
}

void FinishErrorModel(const PreparedErrorModel& prep, const Eigen::VectorXd& x, const RowWeighting& weighting,
                      Robot* identified, EstimationReport* report) {
  FinishErrorModel(prep, x, AccumulateNormalEquations(*prep.problem, x, weighting), identified, report);
}

void FinishErrorModel(const PreparedErrorModel& prep, const Eigen::VectorXd& x, const NormalEquations& ne,
                      Robot* identified, EstimationReport* report) {
  const ErrorModelProblem& problem = *prep.problem;
  problem.WriteToRobot(x, identified);
  const Covariance cov = ComputeCovariance(ne, problem.num_parameters());

  const ErrorModelProblem& p = problem;
  const auto value_of = [&](const ErrorModelParameter& q, const Robot& robot) -> double {
    switch (q.group) {
      case ErrorModelParameter::Group::kJoint:
      case ErrorModelParameter::Group::kTool:
      case ErrorModelParameter::Group::kBase: return robot.model().Parameters()[q.model_index];
      case ErrorModelParameter::Group::kRatio: return robot.drives->ratio[q.joint];
      case ErrorModelParameter::Group::kJointError: return robot.joint_errors.Coefficients()[q.coefficient];
      case ErrorModelParameter::Group::kMarker: return robot.MarkerPosition(q.marker)[q.axis];
      case ErrorModelParameter::Group::kSession: {
        const Eigen::Isometry3d T = robot.SessionBase(q.session);
        return q.axis < 3 ? T.translation()[q.axis] : RpyFromRotation(T.linear())[q.axis - 3];
      }
    }
    return NAN;
  };

  report->parameters.clear();
  std::map<std::string, int> free_index;
  for (int i = 0; i < p.num_parameters(); ++i) free_index[p.parameters()[i].name] = i;
  for (const ErrorModelParameter& candidate : p.candidates()) {
    const ErrorModelParameter* q = &candidate;
    ParameterEstimate e;
    e.name = q->name;
    e.unit = ErrorModelProblem::Unit(*q);
    e.nominal = value_of(*q, prep.input);
    e.value = value_of(*q, *identified);
    const auto it = free_index.find(q->name);
    e.free = it != free_index.end();
    if (e.free) {
      e.stddev = cov.stddev[it->second] * p.ReportScale(*q);
    } else {
      for (const auto& h : p.held()) {
        if (h.parameter.name == q->name) e.note = h.reason;
      }
    }
    report->parameters.push_back(e);
  }
  report->fixed_parameters.clear();
  for (const auto& h : p.held()) {
    if (h.unidentifiable) report->fixed_parameters.push_back(h.parameter.name);
  }
  const IdentifiabilityAnalysis& a = prep.identifiability;
  report->condition_number = a.condition_number;
  report->final_rms = ne.PositionRms();
  for (const auto& w : prep.warnings) report->warnings.push_back(w);

  nlohmann::json& d = report->details;
  d["free_parameters"] = p.num_parameters();
  d["residuals"] = ne.num_residuals;
  d["degrees_of_freedom"] = cov.degrees_of_freedom;
  d["sigma_m"] = Finite(cov.sigma);
  d["cost"] = ne.cost;
  d["registered_start_rms_m"] = Finite(prep.registered_rms);
  d["placed_in_closed_form"] = prep.placed;
  d["rank"] = a.rank;
  d["observability"] = {{"O1", a.observability.o1}, {"O2", a.observability.o2}, {"O3", a.observability.o3},
                        {"O4", a.observability.o4}, {"O5", a.observability.o5},
                        {"scaling", "characteristic: 1 mm, 1 mrad, 1e-3 ratio scale; O1, O3, O4, O5 in m"}};
  d["condition_number_scaling"] = "unit column norms";
  nlohmann::json held = nlohmann::json::array();
  for (const auto& h : p.held()) held.push_back({{"name", h.parameter.name}, {"reason", h.reason}});
  d["held_parameters"] = held;
}

bool FinishIfNothingFree(const PreparedErrorModel& prepared, Robot* identified, EstimationReport* report) {
  if (prepared.problem->num_parameters() != 0) return false;
  report->status = EstimationStatus::kConverged;
  report->message = "no free parameter";
  report->iterations = 0;
  FinishErrorModel(prepared, prepared.problem->InitialX(), prepared.initial, identified, report);
  return true;
}

}  // namespace kincal
