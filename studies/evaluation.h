#pragma once
// Evaluation of one work item: simulate (or split) the dataset of a trial, identify with a pipeline, then
// for every compensator and validation set command the targets and score what the TRUE arm reaches.
//
// Scoring follows the seed's experiment (METHOD.md section 5): a target is a tool pose; the controller
// converts commanded joint angles to motor counts with its nominal ratios; the real arm (the study's truth)
// turns by what those counts mean with its real ratios. "Before" is the nominal solution commanded as is
// (estimator none, compensator none); "after" is what a compensator commands for the identified robot.
// Errors are between the target and the truth's attained tool pose: exact, no measurement noise.
// On measured data "before" (estimator none) is the nominal geometry with only the base and the tool or
// markers fitted to the training rows: the nominal robot unregistered would be metres off.
// Besides the compensators, compensator "-" scores the identified robot alone: its prediction error, at the
// targets' commanded joints, of where the true arm goes. Measured datasets have no truth to command: their
// only score is that prediction on the held-out test rows (compensator "-", validation "heldout").
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "robot/prediction.h"
#include "studies/parameter_rows.h"
#include "studies/study.h"
#include "studies/validation.h"

namespace kincal {

// Distribution of per-target errors (SI: m or rad): the prediction errors' statistics (robot/prediction.h;
// the median is the 50 % quantile) and the quantiles the studies' tables print. NaN everywhere when
// count == 0.
struct ErrorSummary : ErrorStats {
  ErrorSummary() { mean = rms = max = median = NAN; }
  double p05 = NAN, p25 = NAN, p75 = NAN, p95 = NAN;
};
ErrorSummary SummarizeErrors(std::vector<double> errors);

// Compensator convergence at one iteration, over the targets of a validation set (errors against the
// identified model, as the compensator sees them; a target that stopped early keeps its last value).
struct ConvergencePoint {
  int iteration = 0;
  double position_median = NAN, position_max = NAN;        // m
  double orientation_median = NAN, orientation_max = NAN;  // rad
  int active_targets = 0;                                  // targets still iterating
};

struct IsoPoseResult {
  int pose = 1;  // P1..P5
  Iso9283PoseStats stats;
};

// One (compensator, validation set) of a work item.
struct EvaluationRow {
  std::string compensator;
  std::string validation;
  int targets = 0;
  int converged = 0;  // compensations that reported convergence
  ErrorSummary position;
  ErrorSummary orientation;
  std::string status;  // ok, estimate_iteration_limit, estimate_failed, estimate_at_bounds, compensation_partial,
                       // or failed: no scores, the estimator or compensator threw or returned non-finite numbers
                       // (note: why)
  std::string note;
  double compensate_seconds_per_target = NAN;
  std::vector<ConvergencePoint> convergence;  // the study's first random validation set only
  std::vector<IsoPoseResult> iso;             // ISO 9283 sets only
};

// One held-out row of measured data, for the report's error against reach and against approach speed.
struct HeldoutPoint {
  int row = 0;  // index among the test rows, in measurement order
  std::string marker;
  double reach = NAN;            // m: the measured point's distance from the axis of joint 1 (base frame z)
  double approach_speed = NAN;   // rad/s: the fastest joint's speed on its way to the pose when every joint
                                 // moves at the slowest joint's pace (velocity limits); NaN without limits
                                 // or without a previous pose
  double error = NAN;            // m: position error of the identified robot's prediction
  double sd = NAN;               // m: its predicted standard deviation (estimators/error_model/
                                 // prediction_uncertainty.h (2)), NaN when the last estimator gives no covariance
  double tau = NAN;              // m: the model-inadequacy part of sd (0 when the fit did not cross-validate)
  bool outside_support = false;  // the parameters' part of sd above the documented multiple of the training
                                 // rows' median, or a joint beyond the training range
};

// One candidate of a model selection (`select: true`; estimators/selection/model_selection.h).
struct SelectionRow {
  std::string candidate;
  int parameters = 0;
  double cv_rms = NAN, se = NAN;  // m
  bool chosen = false;
};

struct ItemResult {
  WorkItem item;
  std::string estimation_status;  // converged, iteration_limit, failed, error
  std::string estimation_note;
  double identify_seconds = NAN;
  std::vector<EvaluationRow> rows;
  std::vector<ParameterRow> parameters;
  std::vector<HeldoutPoint> heldout;    // measured data only
  std::vector<SelectionRow> selection;  // the last estimator's model selection, if it selected
};

class StudyEvaluator {
 public:
  // Prepares everything shared by the work items (robots per dataset, validation targets, ISO cubes,
  // measured data). Throws std::invalid_argument for problems found here (unreadable data, no cube fits).
  StudyEvaluator(const Study& study, const MethodRegistries& registries = MethodRegistries());

  const Study& study() const { return study_; }
  const std::vector<DatasetVariant>& variants() const { return variants_; }
  const std::vector<WorkItem>& items() const { return items_; }

  // Thread-safe; every failure inside becomes a status in the result.
  ItemResult Run(const WorkItem& item) const;

 private:
  struct PreparedDataset {
    Robot nominal;  // with the dataset's marker as tool
    Robot truth;
    Dataset measured;
    std::vector<std::vector<ValidationTarget>> targets;  // per validation set
    std::vector<bool> orientation;                       // per validation set
  };
  // Run, with every method failure caught; a non-empty `failure` fails the item without running anything.
  ItemResult RunItem(const WorkItem& item, const std::string& failure) const;
  // The item's pipeline (RunPipeline with the injected registries) on its training rows, *test the
  // held-out ones: the reports and *identified; the estimation's status, note and time in *result, the
  // status "error" when a method failed (the note names it).
  std::vector<EstimationReport> Identify(const WorkItem& item, const std::string& failure, Dataset* test,
                                         Robot* identified, ItemResult* result) const;
  Dataset TrainingData(const WorkItem& item, Dataset* test) const;
  void Evaluate(const WorkItem& item, const PreparedDataset& d, const Robot& identified, const std::string& status,
                const std::string& note, ItemResult* result) const;

  const Study& study_;
  MethodRegistries registries_;
  std::vector<DatasetVariant> variants_;
  std::vector<WorkItem> items_;
  std::vector<PreparedDataset> datasets_;
  int convergence_validation_ = -1;
};

}  // namespace kincal
