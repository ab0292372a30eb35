#pragma once
// ErrorModelProblem: the error model that every least-squares-type estimator minimises:
// the difference between measured and predicted marker positions (and tool orientations, where a row
// has one) over the free parameters of a robot.
//
// Unknowns x: the free subset of the candidates below, in this order; each group is contiguous and forms
// one parameter block (blocks(); Ceres parameter blocks, sparsity with sessions):
//   "geometry"      free model parameters other than the base: alpha_i, a_i, theta_i, d_i, tool_*; SI
//   "ratios"        "ratio_i": joint i's reduction ratio RELATIVE TO THE START ROBOT'S, s_i = K_i / K_i,start
//                   (1 at the start). The ratio is a joint-angle scale error: q_actual = q_ref / s_i, where
//                   q_ref is the actual angle with the start robot's ratios (counts 2 pi / (C K_start), or
//                   q_commanded K_controller / K_start; METHOD.md section 3, DriveModel).
//   "joint_errors"  the robot's joint error coefficients (models/joint_errors.h), by their names
//                   ("gravity_2_link3_x", "approach_1_speed", ...); SI (rad/m, rad or s)
//   "marker:<id>"   "marker_<id>_x/_y/_z": a reflector's position in the tool frame, m (dataset `marker`)
//   "base"          free base_* parameters: T_meas_base of session 0 (xyz, then roll-pitch-yaw)
//   "session:<k>"   "session_<k>_x/y/z/roll/pitch/yaw": T_meas_base of session k (dataset `session`), same
//                   parametrisation as the base. Rows of session k do not depend on the model's base.
//   "pivot:<name>"  "pivot_<name>_x/y/z", "point_<name>_x/y/z": a distance rows' pivot, a fixed point
//   "point:<name>"  (m, measurement frame of session 0); "plane_<name>_a/_b/_offset": a plane's normal
//   "plane:<name>"  tangent coordinates about its start normal (rad) and offset (m) (factor.h)
// Residuals of a row (RowResiduals(row) of them, 1 to 6), in metres: the factor of the row's kind
// (factor.h, kinds/), e.g. for a point
//   r[0..2] = p_predicted - p_measured                          (measurement frame of the row's session)
//   r[3..5] = L log(R_predicted R_measured^T)                   (rows with an orientation; L =
//             ErrorModelOptions::orientation_length, m per rad, weighs orientation against position)
// Candidates held at their start value are listed by held() with the reason (options, redundant by
// construction, or not identifiable from the data: see identifiability.h).
//
// How a backend uses it (error_model.h does the common steps):
//   PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options, weighting);
//       // places bases, tool and markers in closed form, holds what the data cannot determine
//   const ErrorModelProblem& problem = *prep.problem;
//   Eigen::VectorXd x = problem.InitialX();
//   auto ws = problem.NewWorkspace();                       // scratch: one per thread
//   Vector6d r; Matrix6Xd J;
//   int k = problem.EvaluateRow(i, x, ws.get(), &r, &J);     // r.head(k), J.topRows(k) (k x num_parameters())
//   ... or AccumulateNormalEquations(problem, x, weighting, ...) for cost, J^T r and J^T J in O(p^2) memory;
//   Ceres: one residual block per row over problem.RowBlocks(i); bounds: problem.Bounds(&lower, &upper).
//   ReanalyzeIdentifiability(x, weighting, &prep, &x);        // true: minimise again from the new x
//   FinishErrorModel(prep, x, weighting, identified, report);  // robot, covariance, report
//
// The problem keeps a pointer to the dataset: the dataset must outlive it. It copies the robots.
// Evaluation is const and thread-compatible: give every thread its own Workspace.
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "estimators/error_model/factor.h"
#include "framework/dataset.h"
#include "framework/math.h"
#include "framework/registry.h"
#include "robot/robot.h"
#include "models/joint_error_regressors.h"
#include "models/joint_errors.h"

namespace kincal {

// Bounds around the start value (after the closed-form placement of bases, tool and markers) for the
// bounded solvers (NLopt, Ipopt).
struct ErrorModelBounds {
  double length = 0.010;  // m: a_i, d_i (and prismatic offsets)
  // rad: alpha_i, theta_i, tool angles. 5 deg: a controller's joint zeros can sit 2 deg from the nominal
  // ones (the IRB 120 of irb120_wu2015), and a bound at 2 deg decided one of them.
  double angle = 5.0 * M_PI / 180.0;
  double ratio = 0.05;                      // relative: s_i in [1 - ratio, 1 + ratio]
  double marker = 0.05;                     // m: marker offsets, and tool_x/y/z (the marker without markers)
  double base_length = 0.10;                // m: base and session-base translations
  double base_angle = 10.0 * M_PI / 180.0;  // rad: base and session-base rotations
  // rad: joint error coefficients, as the RMS over the dataset of the joint offset each one makes
  // (its bound is this over the RMS of its regressor).
  double joint_error = 0.5 * M_PI / 180.0;

  // Keys bound_length, bound_angle_deg, bound_ratio, bound_marker, bound_base_length,
  // bound_base_angle_deg, bound_joint_error_deg.
  static const OptionTable<ErrorModelBounds>& Table();
};

// Gaussian priors (maximum a posteriori; figaroh-plus and industrial_calibration do the same): each
// parameter with a prior adds the pseudo-residual noise * (x_j - mu_j) / sd_j to the cost, mu_j its
// start value, so that the cost is noise^2 times the negative log posterior. Standard deviations by
// kind (key: default under `prior: on`):
//   length 1 mm (a_i, d_i), angle 2 mrad (alpha_i, beta_i), joint_offset 20 mrad (theta_i, or d_i of a
//   prismatic joint), ratio 0.005 (relative), and per joint error type the RMS joint offset one
//   coefficient makes over the dataset, or per unit regressor (1 m of lever arm, 1 rad/s) where the
//   dataset moves it less: gravity 0.5 mrad, harmonic 0.1 mrad, backlash 0.1 mrad, approach 0.1 mrad
//   (a strain-wave gear's transmission error and lost motion are tens of arc seconds). Base, tool, markers and session
//   bases: no prior (free), unless named.
// Keys in the estimator's options: `prior: on|off`, or a map by kind or parameter name, values with a
// unit ("1mm", "2mrad", "0.1deg"; plain numbers SI), e.g. `prior: {length: 0.5mm, theta_2: 5mrad}` (the
// kinds not given keep their defaults; `none` removes a prior); `prior_noise` (length, per residual;
// default 0 = estimated from the residuals at the solution, the fit repeated until it settles).
struct PriorOptions {
  bool enabled = false;
  bool given = false;  // the options name `prior` (on, off or a map); selection turns priors on unless given
  std::map<std::string, double> sd;  // by kind or name, SI (joint error kinds: rad of joint offset); 0: none
  double noise = 0.0;                // m; 0: estimated
  // The defaults above by kind; 0 for an unknown kind.
  static double DefaultSd(const std::string& kind);
  static const std::vector<std::string>& Kinds();
};

class OptionsReader;
// Reads `prior` and `prior_noise` (priors.cc).
void ReadPriorOptions(OptionsReader* reader, PriorOptions* prior);

struct ErrorModelOptions {
  // Held at their start value: parameter names ("a_2", "base_yaw", "ratio_3", "marker_SMR1_x",
  // "session_2_z", "gravity_2_link3_x") or groups: "base", "tool", "ratios", "markers", "sessions",
  // "joint_<i>" (row i), "joint_errors", or a joint error type ("gravity", "harmonic", "backlash",
  // "approach").
  std::vector<std::string> fixed;
  bool identify_ratios = true;         // when the robot has drives (and the data gives them meaning)
  bool identify_markers = true;        // when the dataset has a `marker` column
  bool identify_session_bases = true;  // when the dataset has a `session` column
  // Place the bases (session by session), the tool's translation and the markers in closed form before
  // solving (start_placement.h); what `fixed` holds stays as given. Bounds are centred on the placed start.
  bool initialize_bases = true;
  double orientation_length = 0.1;  // m per rad (L above): 0.1 m equates 1 mrad and 0.1 mm
  // A parameter is not identifiable when its scaled Jacobian column lies within this sine of an angle
  // of the span of the columns kept before it (identifiability.h). Dimensionless.
  double identifiability_tolerance = 1e-6;
  ErrorModelBounds bounds;
  PriorOptions prior;

  // The keys above (fixed, identify_ratios, identify_markers, identify_session_bases, initialize_bases,
  // orientation_length (a length), identifiability_tolerance), the bounds', prior and prior_noise.
  static const OptionTable<ErrorModelOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct ErrorModelParameter {
  enum class Group { kJoint, kTool, kRatio, kJointError, kMarker, kBase, kSession, kFixture };
  enum class Kind { kLength, kAngle, kRatioScale, kCoefficient };
  std::string name;
  Group group = Group::kJoint;
  Kind kind = Kind::kLength;
  int model_index = -1;     // kJoint, kTool, kBase: index into model().Parameters()
  int joint = -1;           // kRatio, kJointError: 0-based joint; kJoint: 0-based row
  int coefficient = -1;     // kJointError: index into the robot's JointErrors::Coefficients()
  std::string unit;         // kJointError: "rad/m", "rad" or "s"
  std::string marker;       // kMarker: id
  int session = 0;          // kSession: session id
  int axis = 0;             // kMarker, kFixture: 0..2 (x, y, z; a plane's a, b, offset); kSession: 0..5
  int fixture = -1;         // kFixture: index into ErrorModelProblem::fixture_slots()
  double start = 0.0;       // start value in x's units (SI; 1 for a ratio scale)
  std::string prior_kind;   // "length", "angle", "joint_offset", "ratio", a joint error type; "" for base,
                            // tool, markers and sessions
  double prior_mean = 0.0;  // x's units: the start value of the first problem (kept when re-analysed)
  double prior_sd = 0.0;    // x's units; 0: no prior
  // What "determined by the data" is judged against: prior_sd, or without a prior the default of its
  // kind (lengths and angles for base, tool, markers and sessions). x's units.
  double reference_sd = 0.0;
};

struct ParameterBlock {
  std::string name;  // "geometry", "ratios", "marker:<id>", "base", "session:<k>"
  int offset = 0;    // first index in x
  int size = 0;
};

// The reason of a parameter held because the options' `fixed` names it.
inline constexpr char kFixedByOptions[] = "fixed by the options";

struct HeldParameter {
  ErrorModelParameter parameter;
  std::string reason;
  bool unidentifiable = false;  // held because the data cannot determine it (identifiability pass)
};

// A fixture the rows name (a pivot, a plane, a fixed point) and its start: the robot file's, or a closed
// form on the start arm (sphere fit, plane fit, centroid) when the file does not give it.
struct FixtureSlot {
  Fixture::Type type = Fixture::Type::kPivot;
  std::string name;
  FixtureValue start;               // factor.h: position, or a plane's (0, 0, offset) and start normal
  double sd = 0.0, sd_angle = 0.0;  // the robot file's prior sds: position or offset (m), normal (rad)
  bool known = false;               // given without an sd: held at its value
};

class ErrorModelProblem {
 public:
  // Scratch for EvaluateRow: a model clone set to x's values, cached until x changes. One per thread;
  // its members are private to the problem.
  struct Workspace {
    std::unique_ptr<KinematicModel> model;
    Eigen::VectorXd x;  // the x the members below were set for
    bool valid = false;
    Eigen::VectorXd scale;                              // s_i per joint
    std::vector<Eigen::Vector3d> markers;               // per marker slot, tool frame
    std::vector<Vector6d> session_pose;                 // xyz, rpy of each session slot's base
    std::vector<Eigen::Isometry3d> session_base;        // T_meas_base per session slot
    std::vector<Eigen::Isometry3d> session_from_base0;  // T_meas(k)_meas(0) = B_k B_0^-1
    JointErrors joint_errors;                           // the start robot's terms with x's coefficients
    JointErrors active_joint_errors;                    // the terms a row evaluates, with x's coefficients
    Eigen::VectorXd qbar, qbar_previous, q;             // drive angles (and the previous pose's), actual angles
    JointErrorMap joint_error_map;
    // The active terms laid out once for the model's structure, and their per-row scratch.
    PreparedRegressors regressors;
    PreparedRegressors::Row regressor_row;
    std::vector<FixtureValue> fixtures;                 // per fixture slot
    Matrix6x3d J_fixture;
    Matrix6Xd J_model;
    Matrix6Xd J_joints;
  };

  // Throws std::invalid_argument for bad input: joint counts, non-finite values, unknown marker ids,
  // unknown names in options.fixed, or fewer residuals than free parameters.
  ErrorModelProblem(const Robot& start, const Robot& controller, const Dataset& data, const ErrorModelOptions& options);
  ~ErrorModelProblem();
  ErrorModelProblem(const ErrorModelProblem&);
  ErrorModelProblem& operator=(const ErrorModelProblem&);

  // A copy with the given entries of x held at their start value (reason in held()).
  ErrorModelProblem Hold(const std::vector<int>& x_indices, const std::string& reason, bool unidentifiable) const;

  int num_parameters() const { return static_cast<int>(free_.size()); }
  int num_rows() const { return static_cast<int>(data_->rows.size()); }
  int num_residuals() const { return num_residuals_; }
  int RowResiduals(int row) const { return rows_->dimension[row]; }

  const std::vector<ErrorModelParameter>& parameters() const { return free_; }
  // Every parameter the problem could free (free or held), in canonical order: the model's parameters,
  // ratios, markers, session bases.
  const std::vector<ErrorModelParameter>& candidates() const { return candidates_; }
  std::vector<std::string> ParameterNames() const;
  const std::vector<HeldParameter>& held() const { return held_; }
  const std::vector<ParameterBlock>& blocks() const { return blocks_; }
  const std::vector<FixtureSlot>& fixture_slots() const { return fixture_slots_; }
  // A fixture parameter's value in robot.fixtures (a plane's a, b about this problem's start normal); the
  // start value when the robot does not have the fixture.
  double FixtureParameterValue(const ErrorModelParameter& p, const Robot& robot) const;
  // Blocks (indices into blocks()) whose parameters row `row` depends on.
  std::vector<int> RowBlocks(int row) const;

  Eigen::VectorXd InitialX() const;
  // Noise standard deviation per residual that weighs the priors (m); 0 until set.
  double prior_noise() const { return prior_noise_; }
  void set_prior_noise(double noise) { prior_noise_ = noise; }
  bool has_priors() const;
  // Takes prior means (by name) and the noise from `other`, the problem this one replaces.
  void InheritPriors(const ErrorModelProblem& other);
  // A priori magnitude of each parameter's error, for column and variable scaling: 1 mm for lengths,
  // 1 mrad for angles, 1e-3 for ratio scales (each moves a marker about 1 mm at 1 m reach), and for a
  // joint error coefficient the value that offsets its joint by 1 mrad RMS over the dataset.
  Eigen::VectorXd CharacteristicScales() const;
  // Start value -/+ the options' bounds.
  void Bounds(Eigen::VectorXd* lower, Eigen::VectorXd* upper) const;

  std::unique_ptr<Workspace> NewWorkspace() const;
  // Residuals of row `row` at x into residual->head(k) and, when jacobian is not null, dr/dx into its
  // first k rows (resized to 6 x num_parameters(); other rows zero). Returns k (3 or 6). Analytic:
  // KinematicModel::ParameterJacobian at the marker, chain rule for ratios, markers and sessions.
  int EvaluateRow(int row, const Eigen::VectorXd& x, Workspace* workspace, Vector6d* residual,
                  Matrix6Xd* jacobian) const;
  // The pose predictor EvaluateRow's factor reads: the row's marker position and tool orientation in
  // the measurement frame of its session, and when pose_jacobian is not null their derivatives with
  // respect to x (6 x num_parameters(): rows 0-2 dp/dx, rows 3-5 the tool's angular velocity per unit of
  // x). Analytic: KinematicModel::ParameterJacobian at the marker, chain rule for ratios, joint errors,
  // markers and sessions.
  void PredictRowPose(int row, const Eigen::VectorXd& x, Workspace* workspace, PredictedPose* pose,
                      Matrix6Xd* pose_jacobian) const;
  // The factor of row `row`'s kind and what it needs beside the pose.
  const MeasurementFactor& RowFactor(int row) const { return *rows_->factor[row]; }
  FactorContext factor_context() const { return {options_.orientation_length}; }

  // Writes x into *robot (a copy of start()): model parameters, drives.ratio, markers, session_bases.
  void WriteToRobot(const Eigen::VectorXd& x, Robot* robot) const;
  // Factor from x's value (and standard deviation) to the value a user reads: 1, except for ratios
  // (K_i = s_i K_i,start).
  double ReportScale(const ErrorModelParameter& p) const;
  // "m", "rad" or "" (ratios); a joint error coefficient's unit ("rad/m", "rad", "s").
  static std::string Unit(const ErrorModelParameter& p);

  const Robot& start() const { return start_; }
  const Robot& controller() const { return controller_; }
  const Dataset& data() const { return *data_; }
  const ErrorModelOptions& options() const { return options_; }
  bool has_ratios() const { return ratios_active_; }

 private:
  // Construction, in order: per-row tables, the joint variables' parameters, every candidate, then the
  // candidates held by the options and by construction (reasons keyed by name, first reason kept).
  struct RowSummary {
    bool any_session0 = false;     // a row in session 0 (the model's base has an effect)
    bool all_marked = true;        // every row names a marker
    bool any_orientation = false;  // a row measures the tool's orientation
  };
  struct Rows;
  RowSummary TabulateRows(Rows* per_row);
  // The previous poses' drive angles, where an active term (or a prior's scale) needs them (after Build).
  void TabulatePreviousPoses(Rows* per_row) const;
  void FindJointParameters();
  void ListCandidates();
  // Fixture slots of the rows (error_model_fixtures.cc): per row in per_row->fixture, their starts,
  // candidates, prior sds and write-back.
  void ListFixtures(Rows* per_row);
  void StartFixture(const Fixture& given, FixtureSlot* slot) const;
  void ListFixtureCandidates();
  double FixturePriorSd(const ErrorModelParameter& p) const;
  void WriteFixtures(const Workspace& ws, Robot* robot) const;
  void HoldFixedByOptions(std::map<std::string, std::string>* reasons) const;
  void HoldByConstruction(const RowSummary& summary, std::map<std::string, std::string>* reasons);
  // Orders the candidates not held into x, blocks and column maps.
  void Build();
  void ClearColumns();
  void UpdateWorkspace(const Eigen::VectorXd& x, Workspace* ws) const;
  // regressor_rms_ at the start values (scales and bounds of the joint error coefficients).
  void MeasureRegressors();
  // prior_kind, prior_sd, reference_sd of the candidates (after MeasureRegressors).
  void AssignPriors();
  JointErrorContext ContextOf(const Workspace& ws) const;
  // EvaluateRow's steps: the row's actual joint angles into ws->q (drive angles, then the joint errors
  // with the previous pose's; returns whether it has one), and the Jacobian columns at the row's pose.
  struct RowPose;
  bool RowJointAngles(int row, bool jacobian, Workspace* ws) const;
  void RowJacobian(const RowPose& pose, Workspace* ws, Matrix6Xd* jacobian) const;

  Robot start_;
  Robot controller_;
  const Dataset* data_ = nullptr;
  ErrorModelOptions options_;
  bool ratios_active_ = false;
  double prior_noise_ = 0.0;

  // Per row, shared by copies (Hold) so that a million rows are stored once.
  struct Rows {
    std::vector<double> q_ref;       // drive angles qbar with the start's ratios, n per row
    std::vector<double> q_prev_ref;  // the same for the row's previous pose (when joint errors use it)
    std::vector<char> has_previous;
    std::vector<int> marker;   // index into marker_ids_, -1 for the tool origin
    std::vector<int> session;  // index into session_ids_, -1 for session 0
    std::vector<int> fixture;  // index into fixture_slots_, -1 for none
    std::vector<const MeasurementFactor*> factor;  // the row's kind (factor.h)
    std::vector<unsigned char> dimension;          // its number of residuals
  };
  std::shared_ptr<const Rows> rows_;
  std::vector<std::string> marker_ids_;
  std::vector<int> session_ids_;
  int num_residuals_ = 0;
  std::vector<int> joint_parameter_;  // model parameter through which joint i's variable enters, -1 unknown

  std::vector<ErrorModelParameter> candidates_;  // every parameter the model could free, canonical order
  std::vector<ErrorModelParameter> free_;
  std::vector<HeldParameter> held_;
  std::vector<ParameterBlock> blocks_;
  std::vector<int> model_column_;                   // per model parameter: x index or -1
  std::vector<int> ratio_column_;                   // per joint: x index or -1
  std::vector<int> joint_error_column_;             // per joint error coefficient: x index or -1
  std::vector<double> regressor_rms_;               // per joint error coefficient: RMS of its regressor over the rows
  std::vector<std::array<int, 3>> marker_column_;   // per marker slot and axis: x index or -1
  std::vector<std::array<int, 6>> session_column_;  // per session slot and axis: x index or -1
  std::vector<int> marker_block_;                   // per marker slot: block index or -1
  std::vector<FixtureSlot> fixture_slots_;
  std::vector<std::array<int, 3>> fixture_column_;  // per fixture slot and axis: x index or -1
  std::vector<int> fixture_block_;                  // per fixture slot: block index or -1
  std::vector<int> session_block_;                  // per session slot: block index or -1
  int geometry_block_ = -1, ratio_block_ = -1, joint_error_block_ = -1, base_block_ = -1;
  // Joint error terms a row evaluates (SelectActiveJointErrors, after Build): those with a free
  // coefficient or a non-zero held one. A term held whole at zero offsets no joint, so its regressors
  // (gravity's with their geometry derivatives are most of a row's cost) are not computed at all.
  void SelectActiveJointErrors();
  JointErrors active_joint_errors_;      // the start's active terms, in the start's order
  std::vector<int> active_coefficient_;  // per active coefficient: its index among the start's coefficients
  bool joint_errors_active_ = false;     // any active term
  bool gravity_terms_ = false;           // any active gravity term
  std::vector<int> coefficient_joints_;  // per joint error coefficient (the start's): the 0-based joint it offsets
};

}  // namespace kincal
