// kincal identify --nominal N.yaml --data DATA.csv --method A[,B...] [--options O.yaml] --out I.yaml
//                 [--report R.json] [--validate HELDOUT.csv] [--select [--audit]] [--no-check]
// First the checks of `kincal check` (doctor/doctor.h): each finding a warning on stderr; the data are
// fitted as given.
// --select: the last method (an error-model estimator) selects among the robot file's nested joint-error
// models by cross-validation (`select: true`, estimators/selection/model_selection.h).
// --audit (with --select and held-out rows): every nested candidate is also fitted on all training rows
// and scored on the held-out ones, beside the chosen one (estimators/selection/selection_audit.h).
// Methods run in order, each refining the robot of the one before (a pipeline). With a `split` column,
// the train rows identify and the test rows validate.
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "doctor/doctor.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "estimators/frames_only_options.h"
#include "estimators/selection/selection_audit.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"

namespace kincal::app {
namespace {

// A warning line longer than this (a list of parameter names) is cut after a whole name, with a count.
constexpr size_t kWarningChars = 240;

nlohmann::json StatsJson(const ErrorStats& s, double scale) {
  return {{"count", s.count}, {"mean", s.mean * scale}, {"rms", s.rms * scale}, {"max", s.max * scale}};
}

// A stage's summary, warnings (a long one shortened: the report has it whole), selection table and
// model inadequacy, on stdout.
void PrintStage(const EstimationReport& r, const std::string& report_path) {
  std::cout << r.BriefReport() << "\n";
  for (const auto& w : r.warnings) {
    std::cout << "  warning: "
              << ShortLine(w, kWarningChars,
                           report_path.empty() ? " (--report R.json lists them all)" : " (all in " + report_path + ")")
              << "\n";
  }
  if (r.details.contains("selection")) std::cout << SelectionTable(r.details["selection"]);
  if (r.details.contains("prediction_covariance")) {  // the model-inadequacy part of the predicted sd
    std::cout << "  " << InadequacySummary(PredictionCovariance::FromJson(r.details["prediction_covariance"]))
              << "\n";
  }
}

// The nominal geometry with only the frames fitted to `train` (base, session bases, tool, markers), as
// the studies' "before" (studies/evaluation.cc): least_squares with every joint row, the joint errors and
// the ratios held. The nominal itself when that fit fails.
Robot RegisteredNominal(const Robot& nominal, const Dataset& train) {
  const YAML::Node options = FramesOnlyOptions(nominal);
  Robot registered;
  try {
    const EstimationReport r = Estimators().Create("least_squares", options)->Estimate(nominal, train, &registered);
    if (r.status != EstimationStatus::kFailed) return registered;
  } catch (const std::exception&) {
    // Data the nominal cannot be registered on (too few rows): the unregistered nominal is what there is.
  }
  return nominal;
}

// The geometry-only model fitted as the identified one was: the same stages, the last with every joint-level
// term held and no selection. False where the robot has no joint-level terms or the last stage cannot hold
// them (not an error-model estimator).
bool FitGeometryOnly(const std::vector<std::string>& methods, std::vector<YAML::Node> options, const Robot& nominal,
                     const Dataset& train, Robot* geometry) {
  if (nominal.joint_errors.terms.empty()) return false;
  try {
    YAML::Node last = options.back() && options.back().IsMap() ? YAML::Clone(options.back())
                                                                : YAML::Node(YAML::NodeType::Map);
    last.remove("select");
    last["fixed"].push_back("joint_errors");
    options.back() = last;
    const std::vector<EstimationReport> reports = RunPipeline(methods, options, nominal, train, geometry);
    return reports.back().status != EstimationStatus::kFailed;
  } catch (const std::exception&) {
    return false;  // a last stage that cannot hold the joint-level terms: nothing to compare with
  }
}

// The identified robot scored on the held-out rows (printed), against the nominal registered on the
// training rows; the report's "validation". With `geometry` (the geometry-only fit on the same rows), a
// model whose held-out RMS exceeds geometry's by more than half gets the status
// heldout_worse_than_geometry, said on stderr and in the report (`status`, `geometry`).
nlohmann::json Validate(const Robot& nominal, const Robot& identified, const Dataset& train, const Dataset& heldout,
                        const EstimationReport& last, const Robot* geometry) {
  nlohmann::json json;
  // "nominal" is the nominal geometry registered on the training rows (base, sessions, tool and
  // markers fitted, as the studies' "before"): the measurement frame alone would make it metres off.
  const Robot registered = RegisteredNominal(nominal, train);
  // The unregistered nominal scores distance and contact rows against the fixtures the robot file gives,
  // and those it does not against the registered nominal's (fitted with the nominal geometry).
  Robot unregistered_robot = nominal;
  for (const Fixture& f : registered.fixtures.items) {
    if (!nominal.fixtures.Find(f.type, f.name)) unregistered_robot.fixtures.items.push_back(f);
  }
  const PredictionErrors unregistered = EvaluatePredictions(nominal, unregistered_robot, heldout);
  const PredictionErrors before = EvaluatePredictions(nominal, registered, heldout);
  const PredictionErrors after = EvaluatePredictions(nominal, identified, heldout);
  const double mm = 1e3;
  std::printf(
      "held-out (%d rows): position error mean %.4f mm, RMS %.4f mm, max %.4f mm (nominal registered on "
      "the training rows: RMS %.4f mm, max %.4f mm)\n",
      after.position_stats.count, after.position_stats.mean * mm, after.position_stats.rms * mm,
      after.position_stats.max * mm, before.position_stats.rms * mm, before.position_stats.max * mm);
  json = {{"unit", "mm"},
          {"identified", StatsJson(after.position_stats, mm)},
          {"nominal", StatsJson(before.position_stats, mm)},
          {"nominal_unregistered", StatsJson(unregistered.position_stats, mm)}};
  json["status"] = "ok";
  if (geometry) {
    const PredictionErrors geo = EvaluatePredictions(nominal, *geometry, heldout);
    json["geometry"] = StatsJson(geo.position_stats, mm);
    const double ratio = after.position_stats.rms / geo.position_stats.rms;
    std::printf("held-out RMS of geometry alone fitted on the same rows: %.4f mm (the model: %.3f x)\n",
                geo.position_stats.rms * mm, ratio);
    if (ratio > 1.5) {
      json["status"] = "heldout_worse_than_geometry";
      std::fprintf(stderr,
                   "kincal: warning: the identified model predicts the held-out rows %.2f x worse than geometry "
                   "alone fitted on the same rows (RMS %.4f mm against %.4f mm): status "
                   "heldout_worse_than_geometry\n",
                   ratio, after.position_stats.rms * mm, geo.position_stats.rms * mm);
    }
  }
  if (last.details.contains("prediction_covariance")) {
    // Prediction uncertainty of the held-out rows (estimators/error_model/prediction_uncertainty.h).
    const PredictionCovariance cov = PredictionCovariance::FromJson(last.details["prediction_covariance"]);
    const std::vector<double> sd = PredictionSd(identified, nominal, heldout, cov);
    const UncertaintyCheck check = CheckUncertainty(after.position, sd, cov, heldout);
    std::printf(
        "held-out prediction sd: %d of %d rows outside what the training poses support (sd > %.4f mm, or a "
        "joint beyond the training range); "
        "%.1f %% of errors within 3 sqrt(sd^2 + sigma_3d^2) (%.1f %% with sigma per axis; %.1f %% of the rows "
        "inside the support)\n",
        check.outside_support, check.rows, cov.SupportThreshold() * mm, 100.0 * check.coverage,
        100.0 * check.coverage_1d, 100.0 * check.coverage_supported);
    json["uncertainty"] = check.ToJson();
  }
  if (after.orientation_stats.count > 0) {  // rows with a measured orientation: its error too, in mrad
    std::printf("held-out (%d rows with orientation): orientation error mean %.4f mrad, RMS %.4f mrad, max %.4f mrad\n",
                after.orientation_stats.count, after.orientation_stats.mean * 1e3, after.orientation_stats.rms * 1e3,
                after.orientation_stats.max * 1e3);
    json["orientation"] = {{"unit", "mrad"}, {"identified", StatsJson(after.orientation_stats, 1e3)}};
  }
  return json;
}

// --audit: every nested candidate of the last stage's start robot fitted on the training rows as the
// selection fits its choice and scored on the held-out rows, into `last`'s details.selection.
void AuditSelection(const std::vector<std::string>& methods, const std::vector<YAML::Node>& options,
                    const Robot& nominal, const Dataset& train, const Dataset& heldout, EstimationReport* last) {
  if (!last->details.contains("selection")) {
    ThrowInputError("identify: --audit: " + methods.back() + " reported no model selection to audit");
  }
  // The last stage started from the robot of the stages before it (deterministic: the same again).
  Robot start = nominal;
  if (methods.size() > 1) {
    const std::vector<std::string> before(methods.begin(), methods.end() - 1);
    RunPipeline(before, options, nominal, train, &start);
  }
  const auto create = [&](const YAML::Node& o) { return Estimators().Create(methods.back(), o); };
  AddAuditToSelection(AuditCandidates(create, AuditFitOptions(options.back()), start, nominal, train, heldout),
                      &last->details["selection"]);
}

}  // namespace

// The options of each stage from the file at options_path (with --select: the last stage's `select:
// true`). Unknown methods, invalid options and a robot a method cannot start from fail before any work,
// naming their files.
std::vector<YAML::Node> StageOptions(const std::vector<std::string>& methods, const std::string& options_path,
                                     bool select, const Robot& nominal, const std::string& nominal_path) {
  for (const auto& m : methods) Estimators().Get(m);
  std::vector<YAML::Node> options = OptionsPerMethod(LoadYamlFile(options_path), methods, options_path);
  if (select) {
    YAML::Node& last = options.back();
    last = last && last.IsMap() ? YAML::Clone(last) : YAML::Node(YAML::NodeType::Map);
    last["select"] = true;
  }
  for (size_t i = 0; i < methods.size(); ++i) {
    const auto estimator = NamingFile(options_path, [&] { return Estimators().Create(methods[i], options[i]); });
    // The first stage starts from the robot file; later stages from its result, in the same convention.
    NamingFile(nominal_path, [&] { estimator->CheckStart(nominal); });
  }
  return options;
}

void AddIdentifyCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("identify", "identify a robot from a dataset (see kincal methods)");
  struct Args {
    std::string nominal, data, method, options, out, report, validate;
    bool select = false;
    bool audit = false;
    bool no_check = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "nominal robot file (the controller's model)")->required();
  cmd->add_option("--data", a->data, "dataset (CSV)")->required();
  cmd->add_option("--method", a->method, "estimator, or a comma-separated pipeline, e.g. geometric,ratio_regression")
      ->required();
  cmd->add_option("--options", a->options, "options file (YAML): a method's options, or keyed by method name");
  cmd->add_option("--out", a->out, "identified robot file to write")->required();
  cmd->add_option("--report", a->report, "JSON report of every stage");
  cmd->add_option("--validate", a->validate, "held-out dataset to score the identified robot on");
  cmd->add_flag("--select", a->select,
                "select the joint-error model by blocked cross-validation (the last method's option select: true)");
  cmd->add_flag("--audit", a->audit,
                "with --select and held-out rows: fit every nested candidate on the training rows and score each "
                "on the held-out rows");
  cmd->add_flag("--no-check", a->no_check, "skip the checks of kincal check that run first (docs/doctor.md)");
  cmd->callback([a]() {
    if (a->audit && !a->select) ThrowInputError("identify: --audit needs --select (it audits the selection)");
    const Robot nominal = ReadRobotFile(a->nominal);
    const Dataset all = ReadDataset(a->data);
    all.Validate(nominal.dof());
    const std::vector<std::string> methods = SplitComma(a->method);
    const std::vector<YAML::Node> options = StageOptions(methods, a->options, a->select, nominal, a->nominal);

    const Dataset train = all.HasSplit() ? all.Subset(Split::kTrain) : all;
    Dataset heldout;
    bool have_heldout = false;
    if (!a->validate.empty()) {
      heldout = ReadDataset(a->validate);
      heldout.Validate(nominal.dof());
      have_heldout = true;
    } else if (all.HasSplit()) {
      heldout = all.Subset(Split::kTest);
      have_heldout = !heldout.rows.empty();
    }
    if (a->audit && !have_heldout) {
      ThrowInputError("identify: --audit needs held-out rows (--validate HELDOUT.csv, or test rows in a split column of " +
                      a->data + ")");
    }

    // The doctor's findings, as warnings: the data are fitted as given. They are said once the fit has
    // read the data, so that input it refuses gets its one line and nothing else.
    std::vector<doctor::Finding> findings;
    if (!a->no_check) findings = NamingFile(a->data, [&] { return doctor::Diagnose(nominal, train); });
    Robot identified;
    std::vector<EstimationReport> reports =
        NamingFile(a->data, [&] { return RunPipeline(methods, options, nominal, train, &identified); });
    for (const auto& f : findings) std::cerr << "warning: " << doctor::FindingLine(f) << "\n";
    if (a->audit) {
      NamingFile(a->data, [&] { AuditSelection(methods, options, nominal, train, heldout, &reports.back()); });
    }
    nlohmann::json json;
    json["stages"] = nlohmann::json::array();
    for (const auto& r : reports) {
      PrintStage(r, a->report);
      json["stages"].push_back(r.ToJson());
    }
    if (have_heldout) {
      Robot geometry;
      const bool compare = NamingFile(a->data, [&] { return FitGeometryOnly(methods, options, nominal, train, &geometry); });
      json["validation"] = Validate(nominal, identified, train, heldout, reports.back(), compare ? &geometry : nullptr);
    }
    // Both outputs are prepared before either is written, and each is written atomically.
    const std::string robot_text = RobotToYaml(identified);
    if (!a->report.empty()) WriteFileAtomically(a->report, json.dump(2) + "\n");
    WriteFileAtomically(a->out, robot_text);
  });
}

}  // namespace kincal::app
