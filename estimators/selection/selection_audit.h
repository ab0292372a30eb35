#pragma once
// The audit of model selection (`kincal identify --select --audit`): how every nested candidate
// (model_selection.h) predicts held-out rows when fitted on all training rows, beside the one the
// one-standard-error rule chose. Cross-validation scores the candidates on the training rows only; the
// audit shows, on rows none of them saw, whether the rule's choice is near the best it could have made
// (the acceptance criterion of README "Real data": the chosen candidate's held-out RMS <= 1.05 x the best
// candidate's, and never above geometry's).
//
// Each candidate is fitted as selection fits its choice (select_error_model.cc): the same estimator and
// options, `select` off and, unless the options name `prior`, the default priors (`prior: on`), from the
// stage's start robot with only the candidate's terms (CandidateRobot), on all training rows. The
// candidate selection chose therefore scores what identify's own result scores. Deterministic: the fits
// are, and the candidates run in order.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "framework/dataset.h"
#include "robot/robot.h"

namespace kincal {

// The options of the audit's fits from those of the selecting stage (a map or null): `select: false` and,
// when they do not name `prior`, `prior: on` (what SelectErrorModel's final fit uses). `options` is not
// changed.
YAML::Node AuditFitOptions(const YAML::Node& options);

struct CandidateHeldOut {
  std::string candidate;  // the name NestedCandidates gives it
  EstimationStatus status = EstimationStatus::kFailed;
  int rows = 0;      // held-out rows scored
  double rms = NAN;  // m: held-out position error
  double max = NAN;  // m
};

// `options` with the candidate's held coefficients added to `fixed` (a compliance candidate's).
YAML::Node CandidateFitOptions(const YAML::Node& options, const SelectionCandidate& candidate);

// The selecting stage's estimator made from options (the registry's Create for its name).
using EstimatorFactory = std::function<std::unique_ptr<Estimator>(const YAML::Node& options)>;

// Fits every nested candidate of `start` on `train` with the estimator `create` makes from
// CandidateFitOptions of `options` (itself from AuditFitOptions) and `controller` (the robot that
// commanded the data, identify's nominal), in NestedCandidates' order, and scores each fit's position
// predictions of `heldout` (EvaluatePredictions). Throws what the estimator throws for bad input.
std::vector<CandidateHeldOut> AuditCandidates(const EstimatorFactory& create, const YAML::Node& options,
                                              const Robot& start, const Robot& controller, const Dataset& train,
                                              const Dataset& heldout);

// Adds to every candidate of `selection` (details.selection, SelectionToJson) held_out_rms_mm,
// held_out_max_mm and held_out_status, and to the table `audit`: held-out rows and the summary line
// (AuditSummary). Throws std::invalid_argument when the candidates differ from the table's (name or count).
void AddAuditToSelection(const std::vector<CandidateHeldOut>& audit, nlohmann::json* selection);

// "chosen X: held-out RMS r mm, best candidate Y: b mm (ratio r/b), geometry g mm" from a table with
// held-out columns (the best: lowest held-out RMS, the first on a tie; geometry: the first candidate).
std::string AuditSummary(const nlohmann::json& selection);

}  // namespace kincal
