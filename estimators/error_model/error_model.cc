#include "estimators/error_model/error_model.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Cholesky>

#include "estimators/error_model/scale_hold.h"
#include "estimators/error_model/start_placement.h"

namespace kincal {
namespace {

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

namespace {

// Builds the problem with every structurally free parameter from prep->start, analyses identifiability
// at its start (the data alone) and holds what the data cannot determine, then prep->weak_held. Prior
// means and noise come from `previous` (the problem this one replaces) or, for the first, from the
// options (prior_noise; when estimated, the RMS per residual of the registered start to begin with).
void AnalyzeAndHold(const Robot& controller, const Dataset& data, const ErrorModelOptions& options,
                    const RowWeighting& weighting, PreparedErrorModel* prep, const ErrorModelProblem* previous) {
  const ErrorModelProblem structural(prep->start, controller, data, options);
  const NormalEquations ne =
      AccumulateNormalEquations(structural, structural.InitialX(), weighting, Accumulate::kNormalEquations, false);
  prep->identifiability = AnalyzeIdentifiability(structural, ne.JtJ, ne.num_rows, options.identifiability_tolerance);
  const IdentifiabilityAnalysis& a = prep->identifiability;
  ErrorModelProblem held = structural;
  const auto hold = [&](const std::string& name, const std::string& reason) {
    const auto names = held.ParameterNames();
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) held = held.Hold({static_cast<int>(it - names.begin())}, reason, true);
  };
  // One at a time, each with its reason: indices refer to `structural`, so map each by name.
  for (size_t k = 0; k < a.unidentifiable.size(); ++k) hold(a.unidentifiable_names[k], a.reasons[k]);
  for (const auto& [name, reason] : prep->weak_held) hold(name, reason);
  const std::string scale = LengthToHoldForScale(held, data, options);
  if (!scale.empty()) hold(scale, "the data carry no length (contacts with unknown fixtures): it sets the scale");
  if (previous) {
    held.InheritPriors(*previous);
  } else {
    held.set_prior_noise(options.prior.noise > 0.0 ? options.prior.noise
                         : ne.num_residuals > 0    ? std::sqrt(ne.irls_squares / ne.num_residuals)
                                                   : 0.0);
  }
  prep->problem = std::make_unique<ErrorModelProblem>(held);
  // The normal equations at the start, restricted to the free columns (same x, same rows): the held
  // problem lists the structural problem's parameters in the same order, minus the held ones.
  NormalEquations& initial = prep->initial;
  initial = ne;
  const auto all = structural.ParameterNames();
  std::vector<int> keep;
  for (const auto& name : held.ParameterNames())
    keep.push_back(static_cast<int>(std::find(all.begin(), all.end(), name) - all.begin()));
  const int p = static_cast<int>(keep.size());
  initial.JtJ.resize(p, p);
  initial.Jtr.resize(p);
  for (int i = 0; i < p; ++i) {
    initial.Jtr[i] = ne.Jtr[keep[i]];
    for (int j = 0; j < p; ++j) initial.JtJ(i, j) = ne.JtJ(keep[i], keep[j]);
  }
  AddPriorTerms(*prep->problem, prep->problem->InitialX(), &initial);
}

// A prep at `solution` with prep's history (input, placement, warnings, weak holds).
PreparedErrorModel RebuiltAt(const Eigen::VectorXd& solution, const RowWeighting& weighting,
                             const PreparedErrorModel& prep) {
  const ErrorModelProblem& old = *prep.problem;
  Robot at_solution;
  old.WriteToRobot(solution, &at_solution);
  PreparedErrorModel next;
  next.input = prep.input;
  next.start = at_solution;
  next.warnings = prep.warnings;
  next.placement_notes = prep.placement_notes;
  next.placed = prep.placed;
  next.registered_rms = prep.registered_rms;
  next.weak = prep.weak;
  next.weak_held = prep.weak_held;
  AnalyzeAndHold(old.controller(), old.data(), old.options(), weighting, &next, &old);
  return next;
}

}  // namespace

NormalEquations NormalEquationsAt(const PreparedErrorModel& prep, const Eigen::VectorXd& x,
                                  const RowWeighting& weighting, Accumulate what, bool with_prior) {
  const PreparedErrorModel::Evaluated* e = prep.evaluated.get();
  if (e && e->x.size() == x.size() && e->x == x && e->weights == weighting.weights &&
      e->loss.type == weighting.loss.type && e->loss.scale == weighting.loss.scale) {
    return with_prior ? e->ne : WithoutPriors(e->ne);
  }
  return AccumulateNormalEquations(*prep.problem, x, weighting, what, with_prior);
}

void KeepNormalEquations(const Eigen::VectorXd& x, const RowWeighting& weighting, NormalEquations ne,
                         PreparedErrorModel* prep) {
  prep->evaluated = std::make_shared<const PreparedErrorModel::Evaluated>(
      PreparedErrorModel::Evaluated{x, weighting.weights, weighting.loss, std::move(ne)});
}

PreparedErrorModel PrepareErrorModel(const Robot& start, const Robot& controller, const Dataset& data,
                                     const ErrorModelOptions& options, const RowWeighting& weighting) {
  PreparedErrorModel prep;
  prep.input = start;
  // A reflector the data name but the robot file does not declare starts at the tool origin, to be
  // placed below, when the options let markers be identified.
  for (const Measurement& m : data.rows) {
    if (m.marker.empty() || start.markers.count(m.marker) || !options.identify_markers) continue;
    bool held = false;
    for (const auto& name : options.fixed)
      held = held || name == "markers" || name.rfind("marker_" + m.marker + "_", 0) == 0;
    if (!held) prep.input.markers[m.marker] = Eigen::Vector3d::Zero();
  }
  prep.start = prep.input;
  // Validates everything (throws) before the registration runs on the data.
  { const ErrorModelProblem check(prep.input, controller, data, options); }
  const StartPlacement placement = PlaceStart(controller, data, options, &prep.start);
  for (const std::string& w : placement.warnings) {
    (w.find("too little to place the markers") != std::string::npos ? prep.placement_notes : prep.warnings)
        .push_back(w);
  }
  prep.placed = placement.placed;
  AnalyzeAndHold(controller, data, options, weighting, &prep, nullptr);
  prep.registered_rms = prep.initial.PositionRms();
  return prep;
}

IdentifiabilityChange CompareIdentifiability(const std::vector<ErrorModelParameter>& candidates,
                                             const std::vector<std::string>& before,
                                             const std::vector<std::string>& after) {
  IdentifiabilityChange c;
  const auto group_of = [&](const std::string& name) {
    for (const auto& q : candidates) {
      if (q.name == name) return q.group;
    }
    return ErrorModelParameter::Group::kBase;
  };
  const auto in = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  for (const auto& name : before) {
    if (in(after, name)) continue;
    c.freed += " " + name;
    c.frees_joint_level = c.frees_joint_level || group_of(name) == ErrorModelParameter::Group::kJointError;
  }
  for (const auto& name : after) {
    if (in(before, name)) continue;
    c.held += " " + name;
    c.holds_geometry = c.holds_geometry || group_of(name) == ErrorModelParameter::Group::kJoint;
  }
  return c;
}

namespace {

// The re-analysis `next` (at a solution of prep) when it may replace prep's: not when it hands the link
// geometry to joint-level terms (IdentifiabilityChange::HandsGeometryToJointLevel); then prep stays and
// its warnings say what was refused, `where` naming the re-analysis ("the first solution", "a restart").
// With `note`, an adopted change is named in the warnings too (the restarts, up to eight, do not).
bool AdoptReanalysis(const std::string& where, bool note, PreparedErrorModel next, PreparedErrorModel* prep) {
  const IdentifiabilityChange change =
      CompareIdentifiability(prep->problem->candidates(), prep->identifiability.unidentifiable_names,
                             next.identifiability.unidentifiable_names);
  if (change.HandsGeometryToJointLevel()) {
    const std::string refused = "identifiability re-analysed at " + where + " would hold" + change.held +
                                " to free" + change.freed + ": the analysis in force kept";
    if (std::find(prep->warnings.begin(), prep->warnings.end(), refused) == prep->warnings.end())
      prep->warnings.push_back(refused);
    return false;
  }
  if (note && (!change.freed.empty() || !change.held.empty())) {
    next.warnings.push_back("identifiability re-analysed at " + where + ":" +
                            (change.freed.empty() ? std::string() : " freed" + change.freed) +
                            (change.held.empty() ? "" : ", held" + change.held));
  }
  *prep = std::move(next);
  return true;
}

}  // namespace

bool ReanalyzeIdentifiability(const Eigen::VectorXd& solution, const RowWeighting& weighting, PreparedErrorModel* prep,
                              Eigen::VectorXd* x) {
  PreparedErrorModel next = RebuiltAt(solution, weighting, *prep);
  *x = solution;
  if (next.identifiability.unidentifiable_names == prep->identifiability.unidentifiable_names) return false;
  if (!AdoptReanalysis("the first solution", true, std::move(next), prep)) return false;
  *x = prep->problem->InitialX();
  return true;
}

void RestartAt(const Eigen::VectorXd& solution, const RowWeighting& weighting, double prior_noise,
               PreparedErrorModel* prep, Eigen::VectorXd* x) {
  prep->problem->set_prior_noise(prior_noise);
  *prep = RebuiltAt(solution, weighting, *prep);
  *x = prep->problem->InitialX();
}

void RestartWithPriorNoise(const Eigen::VectorXd& solution, const RowWeighting& weighting, double prior_noise,
                           PreparedErrorModel* prep, Eigen::VectorXd* x) {
  prep->problem->set_prior_noise(prior_noise);
  *x = solution;
  if (AdoptReanalysis("a restart", false, RebuiltAt(solution, weighting, *prep), prep)) {
    *x = prep->problem->InitialX();
  } else {
    prep->evaluated.reset();  // evaluated with the priors of the previous noise
  }
}

double DataSigma(const NormalEquations& ne, int p) {
  const int dof = ne.num_residuals - p;
  return dof > 0 ? std::sqrt(ne.irls_squares / dof) : NAN;
}

namespace {

// A weak parameter drifts along a flat valley of the cost together with the parameters it trades
// against (beta_1 and the base's pitch by degrees, only the joints' gravity telling them apart). Held
// back at its start value alone, it would leave them where they drifted, far from any fit of the rest: the
// rebuilt problem may then hold them too (a tilted axis 1 makes Hayati's beta_1 redundant with the base),
// and the fit ends many times worse than it started. So the free parameters may follow the held ones back
// along the valley (the estimator also tries the plain reset, and keeps the lower training cost): with
// N = J^T W J (+ the priors' information) at the solution, the quadratic model of the cost with the held
// displacement d_H fixed is least at d_F = -N_FF^-1 N_FH d_H. Left as they are where that solve fails
// (N_FF singular or the result not finite).
void FollowHeldAlongValley(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ, const std::vector<int>& hold,
                           const Eigen::VectorXd& solution, Eigen::VectorXd* restart) {
  const int p = static_cast<int>(solution.size());
  if (JtJ.rows() != p) return;
  std::vector<bool> held(p, false);
  for (int i : hold) held[i] = true;
  std::vector<int> free;
  for (int i = 0; i < p; ++i) {
    if (!held[i]) free.push_back(i);
  }
  if (free.empty()) return;
  const Eigen::VectorXd prior = PriorInformation(problem);
  const int f = static_cast<int>(free.size()), h = static_cast<int>(hold.size());
  Eigen::MatrixXd N_FF(f, f), N_FH(f, h);
  Eigen::VectorXd d_H(h);
  for (int b = 0; b < h; ++b) d_H[b] = (*restart)[hold[b]] - solution[hold[b]];
  for (int a = 0; a < f; ++a) {
    for (int b = 0; b < f; ++b) N_FF(a, b) = JtJ(free[a], free[b]);
    N_FF(a, a) += prior[free[a]];
    for (int b = 0; b < h; ++b) N_FH(a, b) = JtJ(free[a], hold[b]);
  }
  // Column-normalised, where N_FF is best conditioned (units differ by orders of magnitude).
  const Eigen::VectorXd d = N_FF.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!(d.minCoeff() > 0.0)) return;
  const Eigen::VectorXd d_inv = d.cwiseInverse();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(d_inv.asDiagonal() * N_FF * d_inv.asDiagonal());
  if (ldlt.info() != Eigen::Success) return;
  const Eigen::VectorXd d_F = -(d_inv.asDiagonal() * ldlt.solve(d_inv.asDiagonal() * (N_FH * d_H)));
  if (!d_F.allFinite()) return;
  for (int a = 0; a < f; ++a) (*restart)[free[a]] += d_F[a];
}

}  // namespace

bool HoldWeakParameters(const Eigen::VectorXd& solution, const RowWeighting& weighting, HoldRestart how,
                        PreparedErrorModel* prep, Eigen::VectorXd* x) {
  *x = solution;
  const ErrorModelProblem& problem = *prep->problem;
  const NormalEquations ne = NormalEquationsAt(*prep, solution, weighting, Accumulate::kNormalEquations, false);
  const double sigma = DataSigma(ne, problem.num_parameters());
  if (!(sigma > 0.0)) return false;
  std::vector<WeakParameter> weak;
  const std::vector<int> hold = ChooseWeakToHold(problem, ne.JtJ, sigma, &weak);
  for (const auto& w : weak) {
    const bool known =
        std::any_of(prep->weak.begin(), prep->weak.end(), [&](const WeakParameter& v) { return v.name == w.name; });
    if (!known) prep->weak.push_back(w);
  }
  if (hold.empty()) return false;
  Eigen::VectorXd restart = solution;
  for (int i : hold) restart[i] = problem.parameters()[i].prior_mean;  // held at the start value
  if (how == HoldRestart::kFreeFollowValley) FollowHeldAlongValley(problem, ne.JtJ, hold, solution, &restart);
  for (int i : hold) {
    const std::string& name = problem.parameters()[i].name;
    std::string reason = "weakly identifiable, held at its start value (no prior): ";
    for (const auto& w : weak) {
      if (w.name == name) reason += w.Describe();
    }
    prep->weak_held.emplace_back(name, reason);
  }
  RestartAt(restart, weighting, problem.prior_noise(), prep, x);
  return true;
}

double PredictedDecrease(const NormalEquations& ne) {
  const int p = static_cast<int>(ne.Jtr.size());
  if (p == 0) return 0.0;
  if (ne.JtJ.rows() != p) return NAN;
  const Eigen::VectorXd d = ne.JtJ.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!(d.minCoeff() > 0.0)) return NAN;
  const Eigen::VectorXd d_inv = d.cwiseInverse();
  const Eigen::LLT<Eigen::MatrixXd> llt(d_inv.asDiagonal() * ne.JtJ * d_inv.asDiagonal());
  if (llt.info() != Eigen::Success) return NAN;
  const Eigen::VectorXd g = d_inv.asDiagonal() * ne.Jtr;
  return g.dot(llt.solve(g));
}

void NameWeakParameters(const Eigen::VectorXd& x, const RowWeighting& weighting, PreparedErrorModel* prep) {
  const ErrorModelProblem& problem = *prep->problem;
  const NormalEquations ne = NormalEquationsAt(*prep, x, weighting, Accumulate::kNormalEquations, false);
  const double sigma = DataSigma(ne, problem.num_parameters());
  if (!(sigma > 0.0)) return;
  for (const WeakParameter& w : FindWeakParameters(problem, ne.JtJ, sigma)) {
    const bool known =
        std::any_of(prep->weak.begin(), prep->weak.end(), [&](const WeakParameter& v) { return v.name == w.name; });
    if (!known) prep->weak.push_back(w);
  }
}

bool WithinNoiseOfMinimum(const NormalEquations& ne, double sigma) {
  if (ne.Jtr.size() == 0) return true;
  if (!(sigma > 0.0)) return false;
  return PredictedDecrease(ne) <= 0.01 * sigma * sigma;  // NaN compares false
}

bool InFlatValley(const NormalEquations& ne) { return PredictedDecrease(ne) <= 0.01 * ne.cost; }

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
  FinishErrorModel(prep, x, NormalEquationsAt(prep, x, weighting), identified, report);
}

namespace {

// A parameter's value in `robot`, x's report units (the ratio itself, not its scale).
double ValueOf(const ErrorModelParameter& q, const Robot& robot, const ErrorModelProblem& problem) {
  switch (q.group) {
    case ErrorModelParameter::Group::kJoint:
    case ErrorModelParameter::Group::kTool:
    case ErrorModelParameter::Group::kBase:
      return robot.model().Parameters()[q.model_index];
    case ErrorModelParameter::Group::kRatio:
      return robot.drives->ratio[q.joint];
    case ErrorModelParameter::Group::kJointError:
      return robot.joint_errors.Coefficients()[q.coefficient];
    case ErrorModelParameter::Group::kMarker:
      return robot.MarkerPosition(q.marker)[q.axis];
    case ErrorModelParameter::Group::kSession: {
      const Eigen::Isometry3d T = robot.SessionBase(q.session);
      return q.axis < 3 ? T.translation()[q.axis] : RpyFromRotation(T.linear())[q.axis - 3];
    }
    case ErrorModelParameter::Group::kFixture:
      return problem.FixtureParameterValue(q, robot);
  }
  return NAN;
}

// Every candidate parameter of the problem (free or held) with its value, posterior and data-alone sd,
// prior sd and the data's share of the information; held ones with their reason.
std::vector<ParameterEstimate> ParameterEstimates(const PreparedErrorModel& prep, const Robot& identified,
                                                  const Covariance& cov, const Eigen::VectorXd& data_sd) {
  const ErrorModelProblem& p = *prep.problem;
  std::map<std::string, int> free_index;
  for (int i = 0; i < p.num_parameters(); ++i) free_index[p.parameters()[i].name] = i;
  std::vector<ParameterEstimate> out;
  for (const ErrorModelParameter& candidate : p.candidates()) {
    const ErrorModelParameter* q = &candidate;
    ParameterEstimate e;
    e.name = q->name;
    e.unit = ErrorModelProblem::Unit(*q);
    e.nominal = ValueOf(*q, prep.input, p);
    e.value = ValueOf(*q, identified, p);
    const auto it = free_index.find(q->name);
    e.free = it != free_index.end();
    if (q->prior_sd > 0.0) e.prior_sd = q->prior_sd * p.ReportScale(*q);
    e.weak = std::any_of(prep.weak.begin(), prep.weak.end(), [&](const WeakParameter& w) { return w.name == q->name; });
    if (e.free) {
      const int j = it->second;
      e.stddev = cov.stddev[j] * p.ReportScale(*q);
      e.data_sd = data_sd[j] * p.ReportScale(*q);
      // The share of the information that came from the data: 1 - posterior variance / prior variance.
      e.data_share = q->prior_sd > 0.0 ? 1.0 - (cov.stddev[j] * cov.stddev[j]) / (q->prior_sd * q->prior_sd)
                                       : (std::isfinite(cov.stddev[j]) ? 1.0 : NAN);
    } else {
      for (const auto& h : p.held()) {
        if (h.parameter.name == q->name) e.note = h.reason;
      }
    }
    out.push_back(e);
  }
  return out;
}

// details.held_parameters, prior_noise_m, weak_parameters (and weak_determined_by_prior), and the
// warning that names the weak parameters held for want of a prior.
void ReportHeldAndWeak(const PreparedErrorModel& prep, EstimationReport* report) {
  const ErrorModelProblem& p = *prep.problem;
  nlohmann::json& d = report->details;
  nlohmann::json held = nlohmann::json::array();
  for (const auto& h : p.held()) held.push_back({{"name", h.parameter.name}, {"reason", h.reason}});
  d["held_parameters"] = held;
  d["prior_noise_m"] = p.has_priors() ? Finite(p.prior_noise()) : nlohmann::json(nullptr);
  nlohmann::json weak = nlohmann::json::array();
  std::string held_weak, free_weak, loose_weak;
  for (const auto& w : prep.weak) {
    weak.push_back({{"name", w.name},
                    {"data_sd", Finite(w.data_sd)},
                    {"reference_sd", w.reference_sd},
                    {"prior", w.has_prior},
                    {"held", w.held},
                    {"trades_against", w.trades_against}});
    std::string& list = w.held ? held_weak : w.has_prior ? free_weak : loose_weak;
    list += (list.empty() ? "" : ", ") + w.Describe();
  }
  d["weak_parameters"] = weak;
  if (!held_weak.empty()) {
    report->warnings.push_back(
        "weakly identifiable without a prior, held at the start value (add poses that move "
        "them, or give them a prior): " +
        held_weak);
  }
  if (!loose_weak.empty()) {
    report->warnings.push_back(
        "weakly identifiable without a prior, left free where the fit stopped (add poses that move them, or "
        "give them a prior): " +
        loose_weak);
  }
  // Those a prior holds are what priors are for: named in the details and the parameters, not warned of.
  if (!free_weak.empty()) d["weak_determined_by_prior"] = free_weak;
}

}  // namespace

void FinishErrorModel(const PreparedErrorModel& prep, const Eigen::VectorXd& x, const NormalEquations& ne,
                      Robot* identified, EstimationReport* report) {
  const ErrorModelProblem& problem = *prep.problem;
  problem.WriteToRobot(x, identified);
  const Covariance cov = ComputeCovariance(ne, problem.num_parameters());
  // The standard deviations from the data alone (the prior's information removed).
  Eigen::VectorXd data_sd = Eigen::VectorXd::Constant(problem.num_parameters(), NAN);
  if (ne.JtJ.rows() == problem.num_parameters()) {
    Eigen::MatrixXd JtJ_data = ne.JtJ;
    JtJ_data.diagonal() -= PriorInformation(problem);
    data_sd = DataStddev(problem, JtJ_data, cov.sigma, {});
  }
  report->parameters = ParameterEstimates(prep, *identified, cov, data_sd);
  report->fixed_parameters.clear();
  for (const auto& h : problem.held()) {
    if (h.unidentifiable) report->fixed_parameters.push_back(h.parameter.name);
  }
  const IdentifiabilityAnalysis& a = prep.identifiability;
  report->condition_number = a.condition_number;
  report->final_rms = ne.PositionRms();
  for (const auto& w : prep.warnings) report->warnings.push_back(w);

  nlohmann::json& d = report->details;
  d["free_parameters"] = problem.num_parameters();
  d["residuals"] = ne.num_residuals;
  d["degrees_of_freedom"] = cov.degrees_of_freedom;
  d["sigma_m"] = Finite(cov.sigma);
  d["cost"] = ne.cost;
  d["registered_start_rms_m"] = Finite(prep.registered_rms);
  d["placed_in_closed_form"] = prep.placed;
  d["placement_notes"] = prep.placement_notes;
  d["rank"] = a.rank;
  d["observability"] = {
      {"O1", a.observability.o1}, {"O2", a.observability.o2},
      {"O3", a.observability.o3}, {"O4", a.observability.o4},
      {"O5", a.observability.o5}, {"scaling", "characteristic: 1 mm, 1 mrad, 1e-3 ratio scale; O1, O3, O4, O5 in m"}};
  d["condition_number_scaling"] = "unit column norms";
  ReportHeldAndWeak(prep, report);
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
