// Over 600 lines on purpose: ErrorModelProblem's construction (in named steps) and its row evaluation
// share the class's column maps and per-row tables, and are read together; the options' table is here
// beside the problem that reads it.
#include "estimators/error_model/error_model_problem.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "estimators/error_model/pose_jacobians.h"
#include "framework/error.h"
#include "robot/prediction.h"
#include "models/chain_model.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

const char* kAxisNames[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

Vector6d XyzRpy(const Eigen::Isometry3d& T) {
  Vector6d v;
  v.head<3>() = T.translation();
  v.tail<3>() = RpyFromRotation(T.linear());
  return v;
}

// Order of the groups in x (blocks are contiguous).
int GroupOrder(Group g) {
  switch (g) {
    case Group::kJoint:
      return 0;
    case Group::kTool:
      return 0;
    case Group::kRatio:
      return 1;
    case Group::kJointError:
      return 2;
    case Group::kMarker:
      return 3;
    case Group::kBase:
      return 4;
    case Group::kSession:
      return 5;
  }
  return 6;
}

}  // namespace

const OptionTable<ErrorModelBounds>& ErrorModelBounds::Table() {
  using B = ErrorModelBounds;
  static const OptionTable<B> table =
      OptionTable<B>("error model bounds")
          .Add("bound_length", OptionUnit::kLength, &B::length, "bound on a_i, d_i (bounded solvers)", Positive())
          .Add("bound_angle_deg", OptionUnit::kAngleDeg, &B::angle, "bound on alpha_i, theta_i, tool angles",
               Positive())
          .Add("bound_ratio", &B::ratio, "relative bound on the ratio scales", Between(0, 1, true, true))
          .Add("bound_marker", OptionUnit::kLength, &B::marker, "bound on marker offsets and tool_x/y/z", Positive())
          .Add("bound_base_length", OptionUnit::kLength, &B::base_length, "bound on base translations", Positive())
          .Add("bound_base_angle_deg", OptionUnit::kAngleDeg, &B::base_angle, "bound on base rotations", Positive())
          .Add("bound_joint_error_deg", OptionUnit::kAngleDeg, &B::joint_error,
               "bound on a joint error coefficient, as the RMS joint offset it makes", Positive());
  return table;
}

const OptionTable<ErrorModelOptions>& ErrorModelOptions::Table() {
  using O = ErrorModelOptions;
  static const OptionTable<O> table =
      OptionTable<O>("error model")
          .Add("fixed", &O::fixed, "parameter names or groups held at their start value")
          .Add("identify_ratios", &O::identify_ratios, "identify the reduction ratios (robots with drives)")
          .Add("identify_markers", &O::identify_markers, "identify marker offsets (datasets with a marker column)")
          .Add("identify_session_bases", &O::identify_session_bases, "identify each session's base")
          .Add("initialize_bases", &O::initialize_bases, "place bases, tool and markers in closed form first")
          .Add("orientation_length", OptionUnit::kLength, &O::orientation_length,
               "weight of orientation against position, per rad", Positive())
          .Add("identifiability_tolerance", &O::identifiability_tolerance,
               "sine below which a Jacobian column counts as dependent", Between(0, 1, true, true))
          .Include(ErrorModelBounds::Table(), &O::bounds)
          .AddRead({"prior", "on, off or a map", "off (on with select: true)",
                    "Gaussian priors: on (defaults by kind), or sd by kind or name (priors.cc)"},
                   [](OptionsReader* reader, O* o) { ReadPriorOptions(reader, &o->prior); })
          .Document({"prior_noise", "length", "0 m", "noise of the prior's pseudo-residuals; 0: estimated"})
          .Rule({"prior_noise", "prior"}, [](const O& o) -> std::string {
            if (!(o.prior.noise >= 0.0) || !std::isfinite(o.prior.noise)) return "prior_noise must be finite and >= 0";
            for (const auto& [key, sd] : o.prior.sd) {
              if (!(sd >= 0.0) || !std::isfinite(sd)) return "prior: " + key + " must be finite and >= 0";
            }
            return "";
          });
  return table;
}

bool ErrorModelOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

ErrorModelProblem::~ErrorModelProblem() = default;
ErrorModelProblem::ErrorModelProblem(const ErrorModelProblem&) = default;
ErrorModelProblem& ErrorModelProblem::operator=(const ErrorModelProblem&) = default;

ErrorModelProblem::ErrorModelProblem(const Robot& start, const Robot& controller, const Dataset& data,
                                     const ErrorModelOptions& options)
    : start_(start), controller_(controller), data_(&data), options_(options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("error model options: " + OneLine(why));
  if (!start.has_model()) throw std::invalid_argument("error model: the robot has no model");
  const int n = start.dof();
  if (controller.dof() != n)
    throw std::invalid_argument("error model: the controller and the model differ in joint count");
  data.Validate(n);
  if (data.rows.empty()) throw std::invalid_argument(data.source + ": the dataset has no rows");
  if (start.drives) start.drives->Validate(n);
  start.ValidateJointLevel();
  joint_errors_active_ = !start.joint_errors.empty();
  coefficient_joints_ = start.joint_errors.CoefficientJoints();
  for (const auto& t : start.joint_errors.terms)
    gravity_terms_ = gravity_terms_ || t.type == JointErrorTerm::Type::kGravity;

  const RowSummary summary = TabulateRows();
  FindJointParameters();
  ListCandidates();
  std::map<std::string, std::string> reasons;  // the first reason given for a parameter is kept
  HoldFixedByOptions(&reasons);
  HoldByConstruction(summary, &reasons);
  for (const auto& p : candidates_) {
    const auto it = reasons.find(p.name);
    if (it != reasons.end()) held_.push_back({p, it->second, false});
  }
  Build();
  MeasureRegressors();
  AssignPriors();
  for (const auto& entry : options.prior.sd) {
    const std::string& key = entry.first;  // a named reference: C++17 lambdas cannot capture bindings
    const auto& kinds = PriorOptions::Kinds();
    const bool known = std::find(kinds.begin(), kinds.end(), key) != kinds.end() ||
                       std::any_of(candidates_.begin(), candidates_.end(),
                                   [&](const ErrorModelParameter& p) { return p.name == key; });
    if (!known) {
      std::string list;
      for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
      throw std::invalid_argument("error model: prior: '" + key + "' is neither a kind (" + list +
                                  ") nor a parameter of this robot and dataset");
    }
  }

  if (num_residuals_ <= num_parameters()) {
    throw std::invalid_argument(data.source + ": too few measurements: " + std::to_string(num_rows()) + " rows give " +
                                std::to_string(num_residuals_) + " residuals for " + std::to_string(num_parameters()) +
                                " free parameters (add poses or fix parameters)");
  }
}

ErrorModelProblem::RowSummary ErrorModelProblem::TabulateRows() {
  const Dataset& data = *data_;
  const int n = start_.dof();
  std::set<std::string> marker_set;
  std::set<int> session_set;
  for (const Measurement& m : data.rows) {
    if (!m.marker.empty()) marker_set.insert(m.marker);
    if (m.session != 0) session_set.insert(m.session);
  }
  marker_ids_.assign(marker_set.begin(), marker_set.end());
  session_ids_.assign(session_set.begin(), session_set.end());
  for (const auto& id : marker_ids_) start_.MarkerPosition(id);  // throws, naming the id

  const int rows = static_cast<int>(data.rows.size());
  auto per_row = std::make_shared<Rows>();
  per_row->q_ref.resize(static_cast<size_t>(rows) * n);
  per_row->marker.resize(rows);
  per_row->session.resize(rows);
  per_row->orientation.resize(rows);
  const bool previous_used = start_.joint_errors.uses_previous();
  const std::vector<Dataset::Previous> previous =
      previous_used ? data.PreviousPoses() : std::vector<Dataset::Previous>();
  if (previous_used) {
    per_row->q_prev_ref.assign(static_cast<size_t>(rows) * n, 0.0);
    per_row->has_previous.assign(rows, 0);
  }
  RowSummary summary;
  for (int i = 0; i < rows; ++i) {
    const Measurement& m = data.rows[i];
    const Eigen::VectorXd q = DriveAngles(controller_, start_, m);
    if (previous_used) {
      if (const Eigen::VectorXd* q_prev = data.PreviousQ(previous[i])) {
        const std::vector<int64_t>* enc = data.PreviousEncoders(previous[i]);
        Eigen::Map<Eigen::VectorXd>(&per_row->q_prev_ref[static_cast<size_t>(i) * n], n) =
            DriveAngles(controller_, start_, *q_prev, enc ? *enc : std::vector<int64_t>{});
        per_row->has_previous[i] = 1;
      }
    }
    if (!q.allFinite())
      throw std::invalid_argument(data.source + ": row " + std::to_string(i + 1) + ": non-finite joint angle");
    Eigen::Map<Eigen::VectorXd>(&per_row->q_ref[static_cast<size_t>(i) * n], n) = q;
    per_row->marker[i] = m.marker.empty()
                             ? -1
                             : static_cast<int>(std::lower_bound(marker_ids_.begin(), marker_ids_.end(), m.marker) -
                                                marker_ids_.begin());
    per_row->session[i] = m.session == 0
                              ? -1
                              : static_cast<int>(std::lower_bound(session_ids_.begin(), session_ids_.end(), m.session) -
                                                 session_ids_.begin());
    per_row->orientation[i] = m.orientation.has_value();
    if (m.orientation && !m.orientation->coeffs().allFinite()) {
      throw std::invalid_argument(data.source + ": row " + std::to_string(i + 1) + ": non-finite orientation");
    }
    summary.any_session0 |= m.session == 0;
    summary.all_marked &= !m.marker.empty();
    summary.any_orientation |= m.orientation.has_value();
    num_residuals_ += m.orientation ? 6 : 3;
  }
  rows_ = std::move(per_row);
  return summary;
}

void ErrorModelProblem::FindJointParameters() {
  // The parameter through which each joint variable enters (its derivative is the joint's column).
  joint_parameter_.assign(start_.dof(), -1);
  if (const auto* chain = dynamic_cast<const ChainModel*>(&start_.model())) {
    for (const auto& op : chain->ops()) {
      if (op.joint >= 0) joint_parameter_[op.joint] = op.parameter;
    }
  }
}

void ErrorModelProblem::ListCandidates() {
  const KinematicModel& model = start_.model();
  const Eigen::VectorXd& values = model.Parameters();
  for (int j = 0; j < model.num_parameters(); ++j) {
    const ParameterInfo& info = model.parameter_info()[j];
    ErrorModelParameter p;
    p.name = info.name;
    p.group = info.group == ParameterInfo::Group::kJoint  ? Group::kJoint
              : info.group == ParameterInfo::Group::kBase ? Group::kBase
                                                          : Group::kTool;
    p.kind = info.kind == ParameterInfo::Kind::kLength ? Kind::kLength : Kind::kAngle;
    p.model_index = j;
    p.joint = info.joint - 1;
    p.start = values[j];
    candidates_.push_back(p);
  }
  if (start_.drives) {
    for (int i = 0; i < start_.dof(); ++i) {
      ErrorModelParameter p;
      p.name = "ratio_" + std::to_string(i + 1);
      p.group = Group::kRatio;
      p.kind = Kind::kRatioScale;
      p.joint = i;
      p.start = 1.0;
      candidates_.push_back(p);
    }
  }
  const JointErrors& joint_errors = start_.joint_errors;
  const std::vector<std::string> names = joint_errors.CoefficientNames();
  const std::vector<int> joints = joint_errors.CoefficientJoints();
  const std::vector<JointErrorTerm::CoefficientKind> kinds = joint_errors.CoefficientKinds();
  const Eigen::VectorXd c = joint_errors.Coefficients();
  for (int k = 0; k < static_cast<int>(names.size()); ++k) {
    ErrorModelParameter p;
    p.name = names[k];
    p.group = Group::kJointError;
    p.kind = Kind::kCoefficient;
    p.joint = joints[k];
    p.coefficient = k;
    p.unit = kinds[k] == JointErrorTerm::CoefficientKind::kTime             ? "s"
             : kinds[k] == JointErrorTerm::CoefficientKind::kAnglePerLength ? "rad/m"
                                                                            : "rad";
    p.start = c[k];
    candidates_.push_back(p);
  }
  for (const auto& id : marker_ids_) {
    const Eigen::Vector3d position = start_.MarkerPosition(id);
    for (int a = 0; a < 3; ++a) {
      ErrorModelParameter p;
      p.name = "marker_" + id + "_" + kAxisNames[a];
      p.group = Group::kMarker;
      p.kind = Kind::kLength;
      p.marker = id;
      p.axis = a;
      p.start = position[a];
      candidates_.push_back(p);
    }
  }
  for (int k : session_ids_) {
    const Vector6d pose = XyzRpy(start_.SessionBase(k));
    for (int a = 0; a < 6; ++a) {
      ErrorModelParameter p;
      p.name = "session_" + std::to_string(k) + "_" + kAxisNames[a];
      p.group = Group::kSession;
      p.kind = a < 3 ? Kind::kLength : Kind::kAngle;
      p.session = k;
      p.axis = a;
      p.start = pose[a];
      candidates_.push_back(p);
    }
  }
}

void ErrorModelProblem::HoldFixedByOptions(std::map<std::string, std::string>* reasons) const {
  for (const std::string& name : options_.fixed) {
    bool matched = false;
    for (const auto& p : candidates_) {
      const bool group_match =
          (name == "base" && p.group == Group::kBase) || (name == "tool" && p.group == Group::kTool) ||
          (name == "ratios" && p.group == Group::kRatio) || (name == "markers" && p.group == Group::kMarker) ||
          (name == "sessions" && p.group == Group::kSession) ||
          (p.group == Group::kJoint && name == "joint_" + std::to_string(p.joint + 1)) ||
          (p.group == Group::kJointError && (name == "joint_errors" || p.name.rfind(name + "_", 0) == 0));
      if (group_match || p.name == name) {
        reasons->emplace(p.name, "fixed by the options");
        matched = true;
      }
    }
    if (!matched) {
      std::string list;
      for (const auto& p : candidates_) list += (list.empty() ? "" : ", ") + p.name;
      throw std::invalid_argument("error model: cannot fix '" + name +
                                  "': not a parameter of this robot and dataset (groups: base, tool, ratios, markers, "
                                  "sessions, joint_<i>, joint_errors, gravity, harmonic, backlash, approach; names: " +
                                  list + ")");
    }
  }
}

void ErrorModelProblem::HoldByConstruction(const RowSummary& summary, std::map<std::string, std::string>* reasons) {
  const auto hold = [&](const ErrorModelParameter& p, const std::string& reason) { reasons->emplace(p.name, reason); };
  const KinematicModel& model = start_.model();
  ratios_active_ = start_.drives && options_.identify_ratios && (data_->HasEncoders() || controller_.drives);
  for (const auto& p : candidates_) {
    const bool model_parameter = p.group == Group::kJoint || p.group == Group::kTool || p.group == Group::kBase;
    if (model_parameter && !model.FreeMask()[p.model_index]) hold(p, "fixed in the robot's free mask");
    if (p.group == Group::kRatio && !ratios_active_) {
      hold(p, !options_.identify_ratios ? "identify_ratios is off"
                                        : "no encoder counts and no controller drives: the ratios have no effect");
    }
    if (p.group == Group::kMarker && !options_.identify_markers) hold(p, "identify_markers is off");
    if (p.group == Group::kSession && !options_.identify_session_bases) hold(p, "identify_session_bases is off");
    if (p.group == Group::kBase && !summary.any_session0)
      hold(p, "no row in session 0: the model's base has no effect");
    if (model_parameter) {
      const std::string redundant = model.RedundantParameterReason(p.model_index);
      if (!redundant.empty()) hold(p, redundant);
    }
  }
  bool markers_free = true;
  for (const auto& p : candidates_) {
    if (p.group == Group::kMarker && reasons->count(p.name)) markers_free = false;
  }
  const bool no_marker = marker_ids_.empty();
  for (const auto& p : candidates_) {
    if (p.group != Group::kTool) continue;
    const bool translation = p.kind == Kind::kLength;
    if (translation && summary.all_marked && markers_free) {
      hold(p, "redundant with the marker offsets (every row names a marker)");
    } else if (!translation && !summary.any_orientation && (no_marker || markers_free)) {
      hold(p, no_marker ? "no effect on position measurements of the tool origin"
                        : "redundant with the marker offsets (no orientation measured)");
    }
  }
}

void ErrorModelProblem::Build() {
  std::set<std::string> held_names;
  for (const auto& h : held_) held_names.insert(h.parameter.name);
  free_.clear();
  for (const auto& p : candidates_) {
    if (!held_names.count(p.name)) free_.push_back(p);
  }
  std::stable_sort(free_.begin(), free_.end(), [](const ErrorModelParameter& a, const ErrorModelParameter& b) {
    return GroupOrder(a.group) < GroupOrder(b.group);
  });

  const int n = start_.dof();
  model_column_.assign(start_.model().num_parameters(), -1);
  ratio_column_.assign(n, -1);
  joint_error_column_.assign(start_.joint_errors.num_coefficients(), -1);
  marker_column_.assign(marker_ids_.size(), {-1, -1, -1});
  session_column_.assign(session_ids_.size(), {-1, -1, -1, -1, -1, -1});
  marker_block_.assign(marker_ids_.size(), -1);
  session_block_.assign(session_ids_.size(), -1);
  blocks_.clear();
  geometry_block_ = ratio_block_ = joint_error_block_ = base_block_ = -1;
  for (int i = 0; i < num_parameters(); ++i) {
    const ErrorModelParameter& p = free_[i];
    std::string block;
    int* block_index = nullptr;
    switch (p.group) {
      case Group::kJoint:
      case Group::kTool:
        model_column_[p.model_index] = i;
        block = "geometry";
        block_index = &geometry_block_;
        break;
      case Group::kBase:
        model_column_[p.model_index] = i;
        block = "base";
        block_index = &base_block_;
        break;
      case Group::kRatio:
        ratio_column_[p.joint] = i;
        block = "ratios";
        block_index = &ratio_block_;
        break;
      case Group::kJointError:
        joint_error_column_[p.coefficient] = i;
        block = "joint_errors";
        block_index = &joint_error_block_;
        break;
      case Group::kMarker: {
        const int slot =
            static_cast<int>(std::lower_bound(marker_ids_.begin(), marker_ids_.end(), p.marker) - marker_ids_.begin());
        marker_column_[slot][p.axis] = i;
        block = "marker:" + p.marker;
        block_index = &marker_block_[slot];
        break;
      }
      case Group::kSession: {
        const int slot = static_cast<int>(std::lower_bound(session_ids_.begin(), session_ids_.end(), p.session) -
                                          session_ids_.begin());
        session_column_[slot][p.axis] = i;
        block = "session:" + std::to_string(p.session);
        block_index = &session_block_[slot];
        break;
      }
    }
    if (blocks_.empty() || blocks_.back().name != block) {
      *block_index = static_cast<int>(blocks_.size());
      blocks_.push_back({block, i, 0});
    }
    ++blocks_.back().size;
  }
}

ErrorModelProblem ErrorModelProblem::Hold(const std::vector<int>& x_indices, const std::string& reason,
                                          bool unidentifiable) const {
  ErrorModelProblem out(*this);
  for (int i : x_indices) {
    if (i < 0 || i >= num_parameters()) throw std::out_of_range("ErrorModelProblem::Hold: index out of range");
    out.held_.push_back({free_[i], reason, unidentifiable});
  }
  out.Build();
  return out;
}

std::vector<std::string> ErrorModelProblem::ParameterNames() const {
  std::vector<std::string> names;
  for (const auto& p : free_) names.push_back(p.name);
  return names;
}

std::vector<int> ErrorModelProblem::RowBlocks(int row) const {
  std::vector<int> out;
  if (geometry_block_ >= 0) out.push_back(geometry_block_);
  if (ratio_block_ >= 0) out.push_back(ratio_block_);
  if (joint_error_block_ >= 0) out.push_back(joint_error_block_);
  const int marker = rows_->marker[row];
  if (marker >= 0 && marker_block_[marker] >= 0) out.push_back(marker_block_[marker]);
  const int session = rows_->session[row];
  if (session < 0 && base_block_ >= 0) out.push_back(base_block_);
  if (session >= 0 && session_block_[session] >= 0) out.push_back(session_block_[session]);
  return out;
}

Eigen::VectorXd ErrorModelProblem::InitialX() const {
  Eigen::VectorXd x(num_parameters());
  for (int i = 0; i < num_parameters(); ++i) x[i] = free_[i].start;
  return x;
}

Eigen::VectorXd ErrorModelProblem::CharacteristicScales() const {
  Eigen::VectorXd scales = Eigen::VectorXd::Constant(num_parameters(), 1e-3);
  for (int i = 0; i < num_parameters(); ++i) {
    if (free_[i].group == Group::kJointError) scales[i] = 1e-3 / regressor_rms_[free_[i].coefficient];
  }
  return scales;
}

void ErrorModelProblem::Bounds(Eigen::VectorXd* lower, Eigen::VectorXd* upper) const {
  const ErrorModelBounds& b = options_.bounds;
  lower->resize(num_parameters());
  upper->resize(num_parameters());
  for (int i = 0; i < num_parameters(); ++i) {
    const ErrorModelParameter& p = free_[i];
    const bool length = p.kind == Kind::kLength;
    double half = 0.0;
    switch (p.group) {
      case Group::kJoint:
        half = length ? b.length : b.angle;
        break;
      case Group::kTool:
        half = length ? b.marker : b.angle;
        break;
      case Group::kRatio:
        half = b.ratio;
        break;
      case Group::kMarker:
        half = b.marker;
        break;
      case Group::kBase:
      case Group::kSession:
        half = length ? b.base_length : b.base_angle;
        break;
      case Group::kJointError:
        half = b.joint_error / regressor_rms_[p.coefficient];
        break;
    }
    (*lower)[i] = p.start - half;
    (*upper)[i] = p.start + half;
  }
}

JointErrorContext ErrorModelProblem::ContextOf(const Workspace& ws) const {
  JointErrorContext c = JointErrorContextOf(start_);
  c.model = ws.model.get();
  return c;
}

void ErrorModelProblem::MeasureRegressors() {
  const int K = start_.joint_errors.num_coefficients();
  std::vector<double> sum2(K, 0.0);
  if (K > 0) {
    auto ws = NewWorkspace();
    const int n = start_.dof();
    for (int row = 0; row < num_rows(); ++row) {
      const Eigen::Map<const Eigen::VectorXd> qbar(&rows_->q_ref[static_cast<size_t>(row) * n], n);
      Eigen::VectorXd previous;
      if (!rows_->has_previous.empty() && rows_->has_previous[row]) {
        previous = Eigen::Map<const Eigen::VectorXd>(&rows_->q_prev_ref[static_cast<size_t>(row) * n], n);
      }
      const Eigen::VectorXd phi =
          EvaluateRegressors(start_.joint_errors, ContextOf(*ws), qbar, previous.size() ? &previous : nullptr);
      for (int k = 0; k < K; ++k) sum2[k] += phi[k] * phi[k];
    }
  }
  // A regressor that is zero at every row keeps the scale 1, so that its (zero) column reads as "no
  // effect" to the identifiability analysis. Zero includes rounding: a gravity term of a frame whose axis
  // is parallel to the joint's (link3_z of joint 2 on an arm with parallel axes 2 and 3) is a triple
  // product of order 1e-17, and normalised by that RMS its column of rounding noise would pass as an
  // independent, identifiable effect, with a coefficient that runs off to 1e10. Regressors are of order
  // 1 in SI (unit directions, lever arms in m, speeds in rad/s, signs, sines): 1e-9 is far below any real
  // one and far above rounding.
  constexpr double kZeroRegressor = 1e-9;
  regressor_rms_.assign(K, 1.0);
  for (int k = 0; k < K; ++k) {
    const double rms = std::sqrt(sum2[k] / num_rows());
    if (rms > kZeroRegressor && std::isfinite(rms)) regressor_rms_[k] = rms;
  }
}

std::unique_ptr<ErrorModelProblem::Workspace> ErrorModelProblem::NewWorkspace() const {
  auto ws = std::make_unique<Workspace>();
  ws->model = start_.model().Clone();
  ws->joint_errors = start_.joint_errors;
  return ws;
}

void ErrorModelProblem::UpdateWorkspace(const Eigen::VectorXd& x, Workspace* ws) const {
  if (x.size() != num_parameters()) {
    throw std::invalid_argument("error model: x has " + std::to_string(x.size()) + " entries, expected " +
                                std::to_string(num_parameters()));
  }
  if (ws->valid && ws->x.size() == x.size() && ws->x == x) return;
  ws->x = x;
  Eigen::VectorXd values = start_.model().Parameters();
  for (size_t j = 0; j < model_column_.size(); ++j) {
    if (model_column_[j] >= 0) values[j] = x[model_column_[j]];
  }
  ws->model->SetParameters(values);
  const int n = start_.dof();
  ws->scale.setOnes(n);
  for (int i = 0; i < n; ++i) {
    if (ratio_column_[i] >= 0) ws->scale[i] = x[ratio_column_[i]];
  }
  if (joint_errors_active_) {
    Eigen::VectorXd c = start_.joint_errors.Coefficients();
    for (size_t k = 0; k < joint_error_column_.size(); ++k) {
      if (joint_error_column_[k] >= 0) c[static_cast<Eigen::Index>(k)] = x[joint_error_column_[k]];
    }
    ws->joint_errors.SetCoefficients(c);
  }
  ws->markers.resize(marker_ids_.size());
  for (size_t k = 0; k < marker_ids_.size(); ++k) {
    ws->markers[k] = start_.MarkerPosition(marker_ids_[k]);
    for (int a = 0; a < 3; ++a) {
      if (marker_column_[k][a] >= 0) ws->markers[k][a] = x[marker_column_[k][a]];
    }
  }
  const Eigen::Isometry3d base0_inverse = ws->model->base().inverse();
  ws->session_pose.resize(session_ids_.size());
  ws->session_base.resize(session_ids_.size());
  ws->session_from_base0.resize(session_ids_.size());
  for (size_t k = 0; k < session_ids_.size(); ++k) {
    Vector6d pose = XyzRpy(start_.SessionBase(session_ids_[k]));
    for (int a = 0; a < 6; ++a) {
      if (session_column_[k][a] >= 0) pose[a] = x[session_column_[k][a]];
    }
    ws->session_pose[k] = pose;
    ws->session_base[k] = PoseFromXyzRpy(pose.head<3>(), pose.tail<3>());
    ws->session_from_base0[k] = ws->session_base[k] * base0_inverse;
  }
  ws->valid = true;
}

// What RowJacobian needs of the row's pose, from EvaluateRow.
struct ErrorModelProblem::RowPose {
  int marker = -1, session = -1;
  bool has_previous = false, oriented = false;
  Eigen::Vector3d point, p;  // the marker in the tool frame; its predicted position (measurement frame)
  Eigen::Isometry3d T_meas_tool;
  Eigen::Matrix3d orientation_map;  // d(orientation residual) / d(rotation), where oriented
};

bool ErrorModelProblem::RowJointAngles(int row, bool jacobian, Workspace* ws) const {
  const int n = start_.dof();
  const Eigen::Map<const Eigen::VectorXd> q_ref(&rows_->q_ref[static_cast<size_t>(row) * n], n);
  ws->qbar = q_ref.cwiseQuotient(ws->scale);
  // Joint errors (models/joint_errors.h eq. 1) with the previous pose's drive angles.
  const bool has_previous = !rows_->has_previous.empty() && rows_->has_previous[row];
  if (!joint_errors_active_) {
    ws->q = ws->qbar;
    return has_previous;
  }
  JointErrorMap& map = ws->joint_error_map;
  if (has_previous) {
    ws->qbar_previous =
        Eigen::Map<const Eigen::VectorXd>(&rows_->q_prev_ref[static_cast<size_t>(row) * n], n).cwiseQuotient(ws->scale);
  }
  const JointErrorMap::Want want{jacobian && ratio_block_ >= 0, jacobian && ratio_block_ >= 0 && has_previous,
                                 jacobian && geometry_block_ >= 0 && gravity_terms_};
  EvaluateJointErrorMap(ws->joint_errors, ContextOf(*ws), ws->qbar, has_previous ? &ws->qbar_previous : nullptr, want,
                        &map);
  ws->q = map.q;
  return has_previous;
}

int ErrorModelProblem::EvaluateRow(int row, const Eigen::VectorXd& x, Workspace* ws, Vector6d* residual,
                                   Matrix6Xd* jacobian) const {
  UpdateWorkspace(x, ws);
  const Measurement& m = data_->rows[row];
  RowPose pose;
  pose.has_previous = RowJointAngles(row, jacobian != nullptr, ws);
  pose.marker = rows_->marker[row];
  pose.point = pose.marker >= 0 ? ws->markers[pose.marker] : Eigen::Vector3d::Zero();
  Matrix6Xd& Jm = ws->J_model;

  Eigen::Isometry3d& T_meas_tool = pose.T_meas_tool;
  if (jacobian) {
    T_meas_tool = ws->model->ParameterJacobian(ws->q, pose.point, &Jm);
  } else {
    T_meas_tool = ws->model->ForwardKinematics(ws->q);
  }
  pose.session = rows_->session[row];
  if (pose.session >= 0) {
    // T_meas(k)_tool = B_k B_0^-1 T_meas(0)_tool: derivatives rotate with it, the model base drops out.
    const Eigen::Isometry3d& M = ws->session_from_base0[pose.session];
    T_meas_tool = M * T_meas_tool;
    if (jacobian) {
      Jm.topRows<3>() = M.linear() * Jm.topRows<3>();
      Jm.bottomRows<3>() = M.linear() * Jm.bottomRows<3>();
    }
  }
  pose.p = T_meas_tool * pose.point;
  residual->head<3>() = pose.p - m.p;
  pose.oriented = rows_->orientation[row];
  if (pose.oriented) {
    const Eigen::Vector3d phi = RotationLog(T_meas_tool.linear() * m.orientation->toRotationMatrix().transpose());
    residual->tail<3>() = options_.orientation_length * phi;
    pose.orientation_map = options_.orientation_length * LeftJacobianInverseSO3(phi);
  } else {
    residual->tail<3>().setZero();
  }
  if (jacobian) RowJacobian(pose, ws, jacobian);
  return pose.oriented ? 6 : 3;
}

void ErrorModelProblem::RowJacobian(const RowPose& pose, Workspace* ws, Matrix6Xd* jacobian) const {
  const int n = start_.dof();
  const int session = pose.session, marker = pose.marker;
  const JointErrorMap& map = ws->joint_error_map;
  const Matrix6Xd& Jm = ws->J_model;
  Matrix6Xd& J = *jacobian;
  J.setZero(6, num_parameters());
  // The joint columns at the actual angles (measurement frame of the row's session), for the chain rule
  // through ratios and joint errors: the model's own columns where a joint adds to a parameter.
  Matrix6Xd& Jq = ws->J_joints;
  bool all_joint_parameters = true;
  for (int i = 0; i < n; ++i) all_joint_parameters = all_joint_parameters && joint_parameter_[i] >= 0;
  if (joint_errors_active_ || ratio_block_ >= 0) {
    if (all_joint_parameters) {
      Jq.resize(6, n);
      for (int i = 0; i < n; ++i) Jq.col(i) = Jm.col(joint_parameter_[i]);
    } else {
      Jq = ws->model->JointJacobian(ws->q, pose.point);
      if (session >= 0) {
        const Eigen::Matrix3d& R = ws->session_from_base0[session].linear();
        Jq.topRows<3>() = R * Jq.topRows<3>();
        Jq.bottomRows<3>() = R * Jq.bottomRows<3>();
      }
    }
  }
  const bool gravity_geometry = joint_errors_active_ && gravity_terms_ && geometry_block_ >= 0;
  for (size_t j = 0; j < model_column_.size(); ++j) {
    const int c = model_column_[j];
    if (c < 0) continue;
    if (session >= 0 && free_[c].group == Group::kBase) continue;
    J.col(c) = Jm.col(j);
    if (gravity_geometry && free_[c].group != Group::kBase)
      J.col(c) += Jq * map.dq_dparameters.col(static_cast<Eigen::Index>(j));
  }
  for (int i = 0; i < n; ++i) {
    const int c = ratio_column_[i];
    if (c < 0) continue;
    if (!joint_errors_active_) {
      // q_i = q_ref,i / s_i: dq_i/ds_i = -q_i / s_i.
      J.col(c) = Jq.col(i) * (-ws->q[i] / ws->scale[i]);
      continue;
    }
    // qbar_i = q_ref,i / s_i (and the previous pose's likewise), then q = qbar + dq(qbar, qbar_previous).
    Eigen::VectorXd dq_ds = map.dq_dqbar.col(i) * (-ws->qbar[i] / ws->scale[i]);
    if (pose.has_previous) dq_ds += map.dq_dprevious.col(i) * (-ws->qbar_previous[i] / ws->scale[i]);
    J.col(c) = Jq * dq_ds;
  }
  if (joint_errors_active_) {
    const std::vector<int>& joints = coefficient_joints_;
    for (size_t k = 0; k < joint_error_column_.size(); ++k) {
      const int c = joint_error_column_[k];
      if (c >= 0) J.col(c) = Jq.col(joints[k]) * map.phi[static_cast<Eigen::Index>(k)];
    }
  }
  if (marker >= 0) {
    for (int a = 0; a < 3; ++a) {
      const int c = marker_column_[marker][a];
      if (c >= 0) J.col(c).head<3>() = pose.T_meas_tool.linear().col(a);
    }
  }
  if (session >= 0) {
    const Vector6d& session_pose = ws->session_pose[session];
    const Matrix6d Jb = PoseParameterJacobian(session_pose.head<3>(), session_pose.tail<3>(), pose.p);
    for (int a = 0; a < 6; ++a) {
      const int c = session_column_[session][a];
      if (c >= 0) J.col(c) = Jb.col(a);
    }
  }
  if (J.cols() == 0) return;  // every parameter held: no columns to map
  if (pose.oriented) {
    J.bottomRows<3>() = pose.orientation_map * J.bottomRows<3>();
  } else {
    J.bottomRows<3>().setZero();
  }
}

void ErrorModelProblem::WriteToRobot(const Eigen::VectorXd& x, Robot* robot) const {
  auto ws = NewWorkspace();
  UpdateWorkspace(x, ws.get());
  *robot = start_;
  robot->model().SetParameters(ws->model->Parameters());
  robot->joint_errors = ws->joint_errors;
  if (robot->drives && ratios_active_) {
    robot->drives->ratio = start_.drives->ratio.cwiseProduct(ws->scale);
  }
  for (size_t k = 0; k < marker_ids_.size(); ++k) robot->markers[marker_ids_[k]] = ws->markers[k];
  for (size_t k = 0; k < session_ids_.size(); ++k) robot->session_bases[session_ids_[k]] = ws->session_base[k];
}

double ErrorModelProblem::ReportScale(const ErrorModelParameter& p) const {
  return p.group == Group::kRatio ? start_.drives->ratio[p.joint] : 1.0;
}

std::string ErrorModelProblem::Unit(const ErrorModelParameter& p) {
  switch (p.kind) {
    case Kind::kLength:
      return "m";
    case Kind::kAngle:
      return "rad";
    case Kind::kRatioScale:
      return "";
    case Kind::kCoefficient:
      return p.unit;
  }
  return "";
}

}  // namespace kincal
