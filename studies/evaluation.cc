// Over 600 lines on purpose: one class (StudyEvaluator) whose preparation, runs and scoring of a work
// item share its prepared datasets and registries; the scoring steps are named functions above it.
#include "studies/evaluation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "compensators/program.h"
#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/frames_only_options.h"
#include "framework/error.h"
#include "framework/math.h"
#include "framework/median.h"
#include "framework/pose_tables.h"
#include "robot/prediction.h"
#include "studies/measured_iso9283.h"
#include "framework/random.h"

namespace kincal {
namespace {

YAML::Node LoadOptions(const std::string& text) { return text.empty() ? YAML::Node() : YAML::Load(text); }

// Where the true arm's joints go when the controller receives a compensation's commands (encoder counts
// when it has drives), coming from the previous target's commands (robot/joint_readings.h).
Eigen::VectorXd TruthAngles(const Robot& nominal, const Robot& truth, const CompensationResult& r,
                            const Eigen::VectorXd* previous_command) {
  return ActualFromReadings(nominal, truth, r.q_command, previous_command,
                            truth.drives ? r.encoders : std::vector<int64_t>{});
}

// An estimator that stopped with parameters on their bounds found the minimum of a smaller model than
// the one asked for: its status says so rather than "converged".
int ParametersAtBounds(const EstimationReport& r) {
  const auto it = r.details.find("parameters_at_bounds");
  return it != r.details.end() && it->is_number_integer() ? it->get<int>() : 0;
}

std::string WorstStatus(const std::vector<EstimationReport>& reports) {
  std::string status = "converged";
  for (const auto& r : reports) {
    if (r.status == EstimationStatus::kFailed) return "failed";
    if (r.status == EstimationStatus::kIterationLimit) status = "iteration_limit";
    if (status == "converged" && ParametersAtBounds(r) > 0) status = "at_bounds";
  }
  return status;
}

std::vector<ConvergencePoint> Convergence(const std::vector<CompensationReport>& reports) {
  size_t iterations = 0;
  for (const auto& r : reports) iterations = std::max(iterations, r.position_history.size());
  std::vector<ConvergencePoint> out;
  for (size_t i = 0; i < iterations; ++i) {
    ConvergencePoint c;
    c.iteration = static_cast<int>(i);
    std::vector<double> position, orientation;
    for (const auto& r : reports) {
      if (r.position_history.empty()) continue;
      const size_t k = std::min(i, r.position_history.size() - 1);
      position.push_back(r.position_history[k]);
      if (k < r.orientation_history.size()) orientation.push_back(r.orientation_history[k]);
      if (i + 1 < r.position_history.size()) ++c.active_targets;
    }
    c.position_median = Median(position);
    c.position_max = *std::max_element(position.begin(), position.end());
    if (!orientation.empty()) {
      c.orientation_median = Median(orientation);
      c.orientation_max = *std::max_element(orientation.begin(), orientation.end());
    }
    out.push_back(c);
  }
  return out;
}

// The names of the identified robot's parameters that are not finite ("" when all are).
std::string NonFiniteParameters(const Robot& robot) {
  std::string names;
  const KinematicModel& m = robot.model();
  const Eigen::VectorXd p = m.Parameters();
  for (int i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i])) names += (names.empty() ? "" : ", ") + m.parameter_info()[i].name;
  }
  if (robot.drives) {
    for (int j = 0; j < robot.drives->ratio.size(); ++j) {
      if (!std::isfinite(robot.drives->ratio[j]))
        names += (names.empty() ? "" : ", ") + ("ratio_" + std::to_string(j + 1));
    }
  }
  return names;
}

// The message of the exception being handled, whatever its type.
std::string CurrentExceptionText() {
  try {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

std::vector<HeldoutPoint> HeldoutPoints(const Robot& identified, const Dataset& test, const PredictionErrors& e) {
  std::vector<HeldoutPoint> out;
  const Eigen::Isometry3d T_base_meas = identified.model().base().inverse();
  const std::vector<Dataset::Previous> previous = test.PreviousPoses();
  const Eigen::VectorXd& v = identified.velocity_limits;
  for (size_t i = 0; i < test.rows.size() && i < e.position.size(); ++i) {
    const Measurement& m = test.rows[i];
    HeldoutPoint h;
    h.row = static_cast<int>(i);
    h.marker = m.marker;
    h.reach = (T_base_meas * m.p).head<2>().norm();
    h.error = e.position[i];
    const Eigen::VectorXd* from = test.PreviousQ(previous[i]);
    if (from && v.size() == m.q.size()) {
      // The move's duration when all joints arrive together at the slowest joint's pace.
      const Eigen::ArrayXd dq = (m.q - *from).array().abs();
      const double duration = (dq / v.array()).maxCoeff();
      if (duration > 0.0) h.approach_speed = dq.maxCoeff() / duration;
    }
    out.push_back(h);
  }
  return out;
}

// The held-out rows' predicted standard deviations from the last estimator's covariance, when it has one.
void AddPredictionSd(const std::vector<EstimationReport>& reports, const Robot& identified, const Robot& controller,
                     const Dataset& test, std::vector<HeldoutPoint>* points) {
  if (reports.empty() || !reports.back().details.contains("prediction_covariance")) return;
  const PredictionCovariance cov = PredictionCovariance::FromJson(reports.back().details.at("prediction_covariance"));
  const std::vector<double> sd = PredictionSd(identified, controller, test, cov);
  for (size_t i = 0; i < points->size() && i < sd.size(); ++i) {
    (*points)[i].sd = cov.PredictedSd(sd[i], test.rows[i].q);
    (*points)[i].tau = cov.Inadequacy(test.rows[i].q);
    (*points)[i].outside_support = cov.OutsideSupport(sd[i], test.rows[i].q);
  }
}

std::vector<SelectionRow> SelectionRows(const EstimationReport& report) {
  std::vector<SelectionRow> out;
  if (!report.details.contains("selection")) return out;
  for (const auto& c : report.details.at("selection").at("candidates")) {
    SelectionRow r;
    r.candidate = c.at("candidate").get<std::string>();
    r.parameters = c.at("parameters").get<int>();
    r.cv_rms = c.at("cv_rms_mm").get<double>() * 1e-3;
    r.se = c.at("se_mm").get<double>() * 1e-3;
    r.chosen = c.at("chosen").get<bool>();
    out.push_back(r);
  }
  return out;
}

// One validation set's targets compensated as a program (each from the previous commands) and scored on
// the true arm: position and orientation errors, convergence, time per target, ISO 9283 cycles, and the
// reports for the convergence plot when keep_reports. Throws for a non-finite solution.
void ScoreProgram(const Compensator& compensator, const Robot& nominal, const Robot& truth,
                  const std::vector<ValidationTarget>& targets, bool with_orientation, const ValidationSpec& spec,
                  uint64_t dataset_seed, bool keep_reports, EvaluationRow* row) {
  std::vector<double> position, orientation;
  std::vector<CompensationReport> reports;
  double seconds = 0.0;
  const bool iso = spec.kind == ValidationSpec::Kind::kIso9283;
  // The validation targets are a program, compensated in order (each from the previous commands).
  std::vector<CompensationTarget> goals(targets.size());
  for (size_t t = 0; t < goals.size(); ++t) {
    goals[t].T_meas_tool = targets[t].T_meas_tool;
    goals[t].has_orientation = with_orientation;
    goals[t].seed = targets[t].q_nominal;
  }
  std::vector<CompensationResult> results = CompensateProgram(compensator, goals);
  for (size_t t = 0; t < goals.size(); ++t) {
    const ValidationTarget& target = targets[t];
    const CompensationTarget& goal = goals[t];
    CompensationResult& r = results[t];
    if (r.report.non_finite) {
      throw std::runtime_error("returned a non-finite solution at target " + std::to_string(t + 1) + " of " +
                               spec.name);
    }
    seconds += r.report.wall_time_seconds;
    if (r.report.status == CompensationStatus::kConverged) ++row->converged;
    const Eigen::VectorXd q_truth = TruthAngles(nominal, truth, r, t > 0 ? &results[t - 1].q_command : nullptr);
    const Eigen::Isometry3d T = truth.model().ForwardKinematics(q_truth);
    position.push_back((T.translation() - target.T_meas_tool.translation()).norm());
    if (goal.has_orientation) orientation.push_back(RotationAngleBetween(T.linear(), target.T_meas_tool.linear()));
    if (iso) {
      // ISO 9283 cycles: the same commands each cycle; the arm's joints and the instrument add noise.
      Rng rng(Rng::Derive(Rng::Derive(dataset_seed, HashLabel("iso:" + spec.name)), t));
      std::vector<Eigen::Isometry3d> attained;
      for (int cycle = 0; cycle < spec.iso.cycles; ++cycle) {
        Eigen::VectorXd q = q_truth;
        for (int j = 0; j < q.size(); ++j) q[j] += spec.iso.joint_noise * rng.Normal();
        Eigen::Isometry3d Tc = truth.model().ForwardKinematics(q);
        for (int k = 0; k < 3; ++k) Tc.translation()[k] += spec.iso.measurement_noise * rng.Normal();
        attained.push_back(Tc);
      }
      row->iso.push_back({static_cast<int>(t) + 1, ComputeIso9283(target.T_meas_tool, attained)});
    }
    if (keep_reports) reports.push_back(std::move(r.report));
  }
  row->targets = static_cast<int>(targets.size());
  row->position = SummarizeErrors(position);
  row->orientation = SummarizeErrors(orientation);
  row->compensate_seconds_per_target = row->targets ? seconds / row->targets : NAN;
  if (!reports.empty()) row->convergence = Convergence(reports);
  if (row->status == "ok" && row->converged < row->targets) {
    row->status = "compensation_partial";
    row->note = std::to_string(row->converged) + " of " + std::to_string(row->targets) + " targets converged";
  }
}

}  // namespace

ErrorSummary SummarizeErrors(std::vector<double> errors) {
  ErrorSummary s;
  s.count = static_cast<int>(errors.size());
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());  // the sums run in increasing order
  static_cast<ErrorStats&>(s) = Summarize(errors);
  s.p05 = Quantile(errors, 0.05);
  s.p25 = Quantile(errors, 0.25);
  s.p75 = Quantile(errors, 0.75);
  s.p95 = Quantile(errors, 0.95);
  return s;
}

StudyEvaluator::StudyEvaluator(const Study& study, const MethodRegistries& registries)
    : study_(study), registries_(registries) {
  variants_ = Variants(study_);
  items_ = WorkItems(study_, variants_);
  for (size_t v = 0; v < study_.validation.size(); ++v) {
    if (study_.validation[v].kind == ValidationSpec::Kind::kRandom) {
      convergence_validation_ = static_cast<int>(v);
      break;
    }
  }
  for (const DatasetSpec& spec : study_.datasets) {
    PreparedDataset d;
    d.nominal = study_.nominal.robot;
    if (!spec.simulated) {
      if (spec.tables) {
        PoseTables tables;
        tables.joints = spec.file;
        tables.positions = spec.position_tables;
        tables.sequence = spec.sequence_table;
        tables.length_unit = spec.table_length_unit;
        tables.angle_unit = spec.table_angle_unit;
        d.measured = ReadPoseTables(tables, d.nominal.dof());
      } else {
        d.measured = ReadDataset(spec.file);
      }
      d.measured.Validate(d.nominal.dof());
      if (spec.split == DatasetSpec::Split::kColumn && d.measured.Subset(Split::kTest).rows.empty()) {
        ThrowInputError(spec.file, 0, 0,
                        "no test rows: add a split column, or give the dataset split: {test_fraction: F}");
      }
      datasets_.push_back(std::move(d));
      continue;
    }
    d.truth = study_.truth->robot;
    if (spec.marker) {
      for (Robot* r : {&d.nominal, &d.truth}) {
        Eigen::Isometry3d tool = r->model().tool();
        tool.translation() = *spec.marker;
        r->model().SetTool(tool);
      }
    }
    for (const ValidationSpec& v : study_.validation) {
      const bool orientation = v.orientation && d.nominal.dof() >= 6;
      d.orientation.push_back(orientation);
      if (v.kind == ValidationSpec::Kind::kRandom) {
        d.targets.push_back(ReachableRandomTargets(d.nominal, d.truth, v.count, v.joint_limits, orientation,
                                                   ValidationSeed(study_, v)));
      } else {
        try {
          d.targets.push_back(PlaceIso9283Cube(d.nominal, v.iso, orientation, ValidationSeed(study_, v)).poses);
        } catch (const std::invalid_argument& e) {
          ThrowInputError(study_.source, 0, 0,
                          "validation '" + v.name + "' on dataset '" + spec.name + "': " + e.what());
        }
      }
    }
    datasets_.push_back(std::move(d));
  }
}

Dataset StudyEvaluator::TrainingData(const WorkItem& item, Dataset* test) const {
  const DatasetVariant& variant = variants_[item.variant];
  const DatasetSpec& spec = study_.datasets[variant.dataset];
  const PreparedDataset& d = datasets_[variant.dataset];
  const uint64_t seed = DatasetSeed(study_, variant, item.trial);
  if (spec.simulated) {
    SimulatorOptions o = variant.simulator;
    o.seed = seed;
    return Simulate(d.nominal, d.truth, o);
  }
  const Dataset& all = d.measured;
  if (spec.split == DatasetSpec::Split::kColumn) {
    *test = all.Subset(Split::kTest);
    return all.Subset(Split::kTrain);
  }
  // Splits go by pose: the rows of one pose (one per marker, consecutive, same joints) stay together.
  std::vector<size_t> pose_of(all.rows.size());
  size_t poses = 0;
  for (size_t i = 0; i < all.rows.size(); ++i) {
    if (i > 0 && all.rows[i].q != all.rows[i - 1].q) ++poses;
    pose_of[i] = poses;
  }
  if (!all.rows.empty()) ++poses;
  std::vector<bool> is_test(poses, false);
  if (spec.split == DatasetSpec::Split::kEvery) {
    for (size_t i = 0; i < poses; ++i) is_test[i] = (i + 1) % spec.every == 0;
  } else {
    std::vector<size_t> order(poses);
    for (size_t i = 0; i < poses; ++i) order[i] = i;
    Rng rng(seed);
    for (size_t i = poses; i > 1; --i) std::swap(order[i - 1], order[rng.NextU64() % i]);
    const size_t count = static_cast<size_t>(std::llround(spec.test_fraction * poses));
    for (size_t i = 0; i < count; ++i) is_test[order[i]] = true;
  }
  // SelectRows keeps each row's previous pose from the whole sequence (joint errors of the move need it).
  std::vector<int> train_rows, test_rows;
  for (size_t i = 0; i < all.rows.size(); ++i)
    (is_test[pose_of[i]] ? test_rows : train_rows).push_back(static_cast<int>(i));
  *test = all.SelectRows(test_rows);
  return all.SelectRows(train_rows);
}

// A method that throws (anything) or returns non-finite numbers fails its work item (or, for a
// compensator, its rows) with the reason as the note; the study goes on.
ItemResult StudyEvaluator::Run(const WorkItem& item) const {
  try {
    return RunItem(item, "");
  } catch (const std::exception& e) {
    return RunItem(item, std::string("work item failed: ") + e.what());
  } catch (...) {
    return RunItem(item, "work item failed: an exception that is not a std::exception");
  }
}

namespace {

// The estimators of an item's pipeline: the injected ones, where the baseline `none` on measured data is
// the nominal geometry placed in the instrument's frame, only the base and the tool or markers fitted to
// the training rows (kincal's least_squares with FramesOnlyOptions, whatever the stage's options). The
// nominal robot as its file gives it sits in its own base frame, metres away from the tracker's (2568 mm
// on the IRB 120 of ../shared/data): no reference. Simulated data are in the truth's frame.
EstimatorRegistry ItemEstimators(const EstimatorRegistry& injected, const DatasetSpec& spec, const Robot& nominal) {
  EstimatorRegistry registry = injected;
  if (!spec.simulated) {
    const auto placement = [&nominal](const YAML::Node&) {
      return Estimators().Create("least_squares", FramesOnlyOptions(nominal));
    };
    registry.Register({"none", "the nominal geometry placed in the instrument's frame", placement, {}});
  }
  return registry;
}

}  // namespace

std::vector<EstimationReport> StudyEvaluator::Identify(const WorkItem& item, const std::string& failure, Dataset* test,
                                                     Robot* identified, ItemResult* result) const {
  const DatasetSpec& spec = study_.datasets[variants_[item.variant].dataset];
  const PreparedDataset& d = datasets_[variants_[item.variant].dataset];
  const PipelineSpec& pipeline = study_.pipelines[item.pipeline];
  std::vector<EstimationReport> reports;
  std::string method;  // the estimator running, for the note of a failure
  try {
    if (!failure.empty()) throw std::runtime_error(failure);
    const Dataset train = TrainingData(item, test);
    std::vector<YAML::Node> options;
    for (size_t i = 0; i < pipeline.methods.size(); ++i) {
      method = pipeline.methods[i];
      options.push_back(!spec.simulated && method == "none" ? YAML::Node() : LoadOptions(pipeline.options_yaml[i]));
    }
    const EstimatorRegistry registry = ItemEstimators(*registries_.estimators, spec, d.nominal);
    size_t stage = 0;
    try {
      reports = RunPipeline(
          registry, pipeline.methods, options, d.nominal, train, identified,
          [](const Robot& robot) {
            const std::string non_finite = NonFiniteParameters(robot);
            if (!non_finite.empty()) throw std::runtime_error("returned non-finite parameters (" + non_finite + ")");
          },
          &stage);
    } catch (...) {
      method = pipeline.methods[stage];
      throw;
    }
    double seconds = 0.0;
    for (const EstimationReport& r : reports) seconds += r.wall_time_seconds;
    method.clear();
    result->identify_seconds = seconds;
    if (!reports.empty()) result->selection = SelectionRows(reports.back());
    result->estimation_status = WorstStatus(reports);
    for (const auto& r : reports) {
      std::string why = r.status != EstimationStatus::kConverged ? r.message : "";
      if (ParametersAtBounds(r) > 0) {
        why += (why.empty() ? "" : ", ") + std::to_string(ParametersAtBounds(r)) + " parameter(s) on their bounds";
      }
      if (!why.empty())
        result->estimation_note += (result->estimation_note.empty() ? "" : "; ") + r.estimator + ": " + why;
    }
  } catch (...) {
    result->estimation_status = "error";
    result->estimation_note = (method.empty() ? "" : "estimator " + method + ": ") + CurrentExceptionText();
  }
  return reports;
}

ItemResult StudyEvaluator::RunItem(const WorkItem& item, const std::string& failure) const {
  ItemResult result;
  result.item = item;
  const DatasetVariant& variant = variants_[item.variant];
  const DatasetSpec& spec = study_.datasets[variant.dataset];
  const PreparedDataset& d = datasets_[variant.dataset];

  Dataset test;
  Robot identified = d.nominal;
  const std::vector<EstimationReport> reports = Identify(item, failure, &test, &identified, &result);
  if (result.estimation_status != "error") {
    result.parameters = ParameterRows(d.nominal, spec.simulated ? &d.truth : nullptr, identified, reports);
  }
  std::string status = "ok";
  if (result.estimation_status == "error") {
    status = "failed";
  } else if (result.estimation_status != "converged") {
    status = "estimate_" + result.estimation_status;
  }

  if (!spec.simulated) {
    EvaluationRow row;
    row.compensator = "-";
    row.validation = "heldout";
    row.status = status;
    row.note = result.estimation_note;
    if (result.estimation_status != "error") {
      const PredictionErrors e = EvaluatePredictions(d.nominal, identified, test);
      row.targets = row.converged = static_cast<int>(test.rows.size());
      row.position = SummarizeErrors(e.position);
      row.orientation = SummarizeErrors(e.orientation);
      result.heldout = HeldoutPoints(identified, test, e);
      AddPredictionSd(reports, identified, d.nominal, test, &result.heldout);
    }
    result.rows.push_back(row);
    if (spec.iso9283) {  // the test rows' repeated poses, and the prediction errors at their visits
      EvaluationRow iso = row;
      iso.validation = "iso9283";
      iso.targets = iso.converged = 0;
      iso.position = iso.orientation = ErrorSummary();
      if (result.estimation_status != "error") {
        const PredictionErrors e = EvaluatePredictions(d.nominal, identified, test);
        const bool all_oriented = e.orientation.size() == test.rows.size();
        std::vector<double> position, orientation;
        for (const MeasuredIsoPose& p : MeasuredIso9283(
                 d.nominal, identified, test, {spec.iso.tolerance, spec.iso.angle_tolerance}, spec.iso.min_cycles)) {
          iso.iso.push_back({p.pose, p.stats});
          for (int r : p.rows) {
            position.push_back(e.position[r]);
            if (all_oriented) orientation.push_back(e.orientation[r]);
          }
        }
        iso.targets = iso.converged = static_cast<int>(position.size());
        iso.position = SummarizeErrors(position);
        iso.orientation = SummarizeErrors(orientation);
      }
      result.rows.push_back(iso);
    }
    return result;
  }
  Evaluate(item, d, identified, status, result.estimation_note, &result);
  return result;
}

void StudyEvaluator::Evaluate(const WorkItem& item, const PreparedDataset& d, const Robot& identified,
                              const std::string& status, const std::string& note, ItemResult* result) const {
  const DatasetVariant& variant = variants_[item.variant];
  const uint64_t dataset_seed = DatasetSeed(study_, variant, item.trial);
  const bool estimated = result->estimation_status != "error";
  // Compensator "-": how well the identified robot predicts where the true arm goes at the targets'
  // commanded joints (it scores an estimator alone, like the held-out rows of measured data).
  for (size_t v = 0; v < study_.validation.size(); ++v) {
    if (study_.validation[v].kind != ValidationSpec::Kind::kRandom) continue;
    EvaluationRow row;
    row.compensator = "-";
    row.validation = study_.validation[v].name;
    row.status = status;
    row.note = note;
    if (estimated) {
      std::vector<double> position, orientation;
      // The targets are a program: each is reached from the one before.
      Dataset program;
      program.dof = d.nominal.dof();
      for (const ValidationTarget& target : d.targets[v]) {
        Measurement m;
        m.q = target.q_nominal;
        if (d.nominal.drives) m.encoders = d.nominal.drives->CommandCounts(m.q);
        program.rows.push_back(std::move(m));
      }
      const std::vector<Dataset::Previous> previous = program.PreviousPoses();
      for (size_t t = 0; t < program.rows.size(); ++t) {
        const Eigen::Isometry3d T_truth =
            d.truth.model().ForwardKinematics(ActualJointAngles(d.nominal, d.truth, program, t, previous));
        const Eigen::Isometry3d T_model =
            identified.model().ForwardKinematics(ActualJointAngles(d.nominal, identified, program, t, previous));
        position.push_back((T_truth.translation() - T_model.translation()).norm());
        if (d.orientation[v]) orientation.push_back(RotationAngleBetween(T_truth.linear(), T_model.linear()));
      }
      row.targets = row.converged = static_cast<int>(d.targets[v].size());
      row.position = SummarizeErrors(position);
      row.orientation = SummarizeErrors(orientation);
    }
    result->rows.push_back(row);
  }
  for (const CompensatorSpec& c : study_.compensators) {
    std::vector<EvaluationRow> rows(study_.validation.size());
    for (size_t v = 0; v < rows.size(); ++v) {
      rows[v].compensator = c.name;
      rows[v].validation = study_.validation[v].name;
      rows[v].status = status;
      rows[v].note = note;
    }
    if (!estimated) {
      for (auto& row : rows) result->rows.push_back(row);
      continue;
    }
    try {
      const auto compensator = registries_.compensators->Create(c.method, LoadOptions(c.options_yaml));
      compensator->Prepare(d.nominal, identified);
      for (size_t v = 0; v < rows.size(); ++v) {
        const ValidationSpec& spec = study_.validation[v];
        ScoreProgram(*compensator, d.nominal, d.truth, d.targets[v], d.orientation[v], spec, dataset_seed,
                     static_cast<int>(v) == convergence_validation_, &rows[v]);
      }
    } catch (...) {
      const std::string reason = "compensator " + c.method + ": " + CurrentExceptionText();
      for (auto& row : rows) {
        EvaluationRow failed;
        failed.compensator = c.name;
        failed.validation = row.validation;
        row = failed;
        row.status = "failed";
        row.note = reason;
      }
    }
    for (auto& row : rows) result->rows.push_back(std::move(row));
  }
}

}  // namespace kincal
