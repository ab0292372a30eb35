// ErrorModelProblem (error_model_problem.h): the options' tables beside the problem that reads them, the
// constructor (its steps in error_model_candidates.cc), copies with parameters held, x's layout, bounds
// and the write-back to a robot. One row's evaluation is in error_model_row.cc.
#include "estimators/error_model/error_model_problem.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "framework/error.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

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
  coefficient_joints_ = start.joint_errors.CoefficientJoints();

  // The per-row tables are filled here and then shared, read-only, by every copy (Hold).
  const auto per_row = std::make_shared<Rows>();
  const RowSummary summary = TabulateRows(per_row.get());
  ListFixtures(per_row.get());
  rows_ = per_row;
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
  TabulatePreviousPoses(per_row.get());
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
  const int fixture = rows_->fixture[row];
  if (fixture >= 0 && fixture_block_[fixture] >= 0) out.push_back(fixture_block_[fixture]);
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
      case Group::kFixture:
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
  WriteFixtures(*ws, robot);
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
