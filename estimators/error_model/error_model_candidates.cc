// ErrorModelProblem's construction steps (error_model_problem.h): the per-row tables, every candidate
// parameter, the candidates held by the options and by construction, the order of x (columns and
// blocks), and the joint error regressors' scale.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/pose_jacobians.h"
#include "models/chain_model.h"
#include "robot/prediction.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

const char* kAxisNames[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

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
    case Group::kFixture:
      return 6;
  }
  return 7;
}

}  // namespace

ErrorModelProblem::RowSummary ErrorModelProblem::TabulateRows(Rows* per_row) {
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
  per_row->q_ref.resize(static_cast<size_t>(rows) * n);
  per_row->marker.resize(rows);
  per_row->session.resize(rows);
  per_row->factor.resize(rows);
  per_row->dimension.resize(rows);
  RowSummary summary;
  for (int i = 0; i < rows; ++i) {
    const Measurement& m = data.rows[i];
    const Eigen::VectorXd q = DriveAngles(controller_, start_, m);
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
    per_row->factor[i] = &FactorOfKind(MeasurementKindName(m.kind));
    per_row->dimension[i] = static_cast<unsigned char>(per_row->factor[i]->Dimension(m));
    if (m.orientation && !m.orientation->coeffs().allFinite()) {
      throw std::invalid_argument(data.source + ": row " + std::to_string(i + 1) + ": non-finite orientation");
    }
    summary.any_session0 |= m.session == 0;
    summary.all_marked &= !m.marker.empty();
    summary.any_orientation |= m.orientation.has_value();
    num_residuals_ += per_row->dimension[i];
  }
  return summary;
}

void ErrorModelProblem::TabulatePreviousPoses(Rows* per_row) const {
  // Backlash and approach terms read the previous pose. Held whole at zero, they are not evaluated, so
  // the previous poses are neither converted nor stored, unless priors report every candidate's scale
  // (MeasureRegressors).
  const bool used =
      active_joint_errors_.uses_previous() || (options_.prior.enabled && start_.joint_errors.uses_previous());
  if (!used) return;
  const Dataset& data = *data_;
  const int n = start_.dof();
  const int rows = static_cast<int>(data.rows.size());
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  per_row->q_prev_ref.assign(static_cast<size_t>(rows) * n, 0.0);
  per_row->has_previous.assign(rows, 0);
  for (int i = 0; i < rows; ++i) {
    if (const Eigen::VectorXd* q_prev = data.PreviousQ(previous[i])) {
      const std::vector<int64_t>* enc = data.PreviousEncoders(previous[i]);
      Eigen::Map<Eigen::VectorXd>(&per_row->q_prev_ref[static_cast<size_t>(i) * n], n) =
          DriveAngles(controller_, start_, *q_prev, enc ? *enc : std::vector<int64_t>{});
      per_row->has_previous[i] = 1;
    }
  }
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
  ListFixtureCandidates();
  for (int k : session_ids_) {
    const Vector6d pose = XyzRpyFromPose(start_.SessionBase(k));
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
          (name == "sessions" && p.group == Group::kSession) || (name == "fixtures" && p.group == Group::kFixture) ||
          (p.group == Group::kJoint && name == "joint_" + std::to_string(p.joint + 1)) ||
          (p.group == Group::kJointError && (name == "joint_errors" || p.name.rfind(name + "_", 0) == 0));
      if (group_match || p.name == name) {
        reasons->emplace(p.name, kFixedByOptions);
        matched = true;
      }
    }
    if (!matched) {
      std::string list;
      for (const auto& p : candidates_) list += (list.empty() ? "" : ", ") + p.name;
      throw std::invalid_argument("error model: cannot fix '" + name +
                                  "': not a parameter of this robot and dataset (groups: base, tool, ratios, markers, "
                                  "sessions, fixtures, joint_<i>, joint_errors, gravity, harmonic, backlash, approach; "
                                  "names: " +
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
    if (p.group == Group::kFixture && fixture_slots_[p.fixture].known)
      hold(p, "known: given in the robot file without an sd");
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

// Every column and block index back to "not free" (-1), sized for the start's model and the data's
// markers, sessions and fixtures.
void ErrorModelProblem::ClearColumns() {
  model_column_.assign(start_.model().num_parameters(), -1);
  ratio_column_.assign(start_.dof(), -1);
  joint_error_column_.assign(start_.joint_errors.num_coefficients(), -1);
  marker_column_.assign(marker_ids_.size(), {-1, -1, -1});
  session_column_.assign(session_ids_.size(), {-1, -1, -1, -1, -1, -1});
  marker_block_.assign(marker_ids_.size(), -1);
  session_block_.assign(session_ids_.size(), -1);
  fixture_column_.assign(fixture_slots_.size(), {-1, -1, -1});
  fixture_block_.assign(fixture_slots_.size(), -1);
  blocks_.clear();
  geometry_block_ = ratio_block_ = joint_error_block_ = base_block_ = -1;
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

  ClearColumns();
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
      case Group::kFixture: {
        const FixtureSlot& slot = fixture_slots_[p.fixture];
        fixture_column_[p.fixture][p.axis] = i;
        block = FixtureTypeName(slot.type) + ":" + slot.name;
        block_index = &fixture_block_[p.fixture];
        break;
      }
    }
    if (blocks_.empty() || blocks_.back().name != block) {
      *block_index = static_cast<int>(blocks_.size());
      blocks_.push_back({block, i, 0});
    }
    ++blocks_.back().size;
  }
  SelectActiveJointErrors();
}

void ErrorModelProblem::SelectActiveJointErrors() {
  // Equation (1) of models/joint_errors.h: a term whose coefficients are all held at zero adds
  // 0 * phi = 0 to its joint and to every derivative, so leaving it out changes no value, not even
  // in the last bit.
  active_joint_errors_.terms.clear();
  active_coefficient_.clear();
  gravity_terms_ = false;
  int k = 0;
  for (const JointErrorTerm& t : start_.joint_errors.terms) {
    const int m = static_cast<int>(t.keys.size());
    bool active = false;
    for (int j = 0; j < m; ++j) active = active || joint_error_column_[k + j] >= 0 || t.coefficients[j] != 0.0;
    if (active) {
      active_joint_errors_.terms.push_back(t);
      for (int j = 0; j < m; ++j) active_coefficient_.push_back(k + j);
      gravity_terms_ = gravity_terms_ || t.type == JointErrorTerm::Type::kGravity;
    }
    k += m;
  }
  joint_errors_active_ = !active_joint_errors_.empty();
}

void ErrorModelProblem::MeasureRegressors() {
  const int K = start_.joint_errors.num_coefficients();
  std::vector<double> sum2(K, 0.0);
  // Without priors only the active terms' scales are read (CharacteristicScales and Bounds: free
  // coefficients); with priors every candidate's prior sd is reported, held ones included.
  const bool every_term = options_.prior.enabled;
  const JointErrors& measured = every_term ? start_.joint_errors : active_joint_errors_;
  std::vector<int> index = active_coefficient_;  // per measured coefficient: its index among the start's
  if (every_term) {
    index.resize(K);
    for (int k = 0; k < K; ++k) index[k] = k;
  }
  if (!index.empty()) {
    auto ws = NewWorkspace();
    const JointErrorContext context = ContextOf(*ws);
    const PreparedRegressors prepared(measured, *ws->model);
    PreparedRegressors::Row regressors;
    const int n = start_.dof();
    for (int row = 0; row < num_rows(); ++row) {
      const Eigen::Map<const Eigen::VectorXd> qbar(&rows_->q_ref[static_cast<size_t>(row) * n], n);
      Eigen::VectorXd previous;
      if (!rows_->has_previous.empty() && rows_->has_previous[row]) {
        previous = Eigen::Map<const Eigen::VectorXd>(&rows_->q_prev_ref[static_cast<size_t>(row) * n], n);
      }
      prepared.Evaluate(context, qbar, previous.size() ? &previous : nullptr, {}, &regressors);
      const Eigen::VectorXd& phi = regressors.phi;
      for (size_t a = 0; a < index.size(); ++a)
        sum2[index[a]] += phi[static_cast<Eigen::Index>(a)] * phi[static_cast<Eigen::Index>(a)];
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

}  // namespace kincal
