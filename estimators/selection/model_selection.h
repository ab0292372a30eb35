#pragma once
// Model selection among nested joint-level error models (option `select: true` of the error-model
// estimators, `kincal identify --select`): which of the robot file's joint-error terms the training data
// support, judged by how well each model predicts rows it was not fitted on.
//
// Candidates (NestedCandidates), nested: geometry only (no joint-error term), then the file's terms added
// one group at a time, a group being one type on one joint, types in the order gravity, harmonic,
// backlash, approach and joints in increasing order within a type (gravity 2, gravity 3, ..., harmonic 1,
// ...), up to the full file. Every candidate keeps everything else the estimator frees (geometry, base,
// tool, ratios, markers, sessions).
//
// Score: blocked K-fold cross-validation on the training rows only (K = select_folds, default 5). The rows
// of each session, in measurement order, are cut into K contiguous blocks of near-equal size; fold k
// holds out block k of every session (so every session keeps training rows to register its base) and
// fits on the rest. Contiguous blocks keep each row's previous pose (Dataset::SelectRows remembers it),
// so backlash and approach terms mean in a fold what they mean in the whole sequence.
// Per fold, cheaply (Hastie, Tibshirani and Friedman, ESL 7.10 for the rule; the refit is one
// Gauss-Newton step):
//   1. the estimator fits geometry only (candidate 0) on the fold's training rows;
//   2. one pass over all training rows at that fit with every joint-error term of the file at its start
//      value gives, from the analytic Jacobian of the error model (error_model_problem.h), the normal
//      equations of the fold's training rows (A = J^T W J, b = J^T W r) and the position-only sums of
//      the held-out block (A_t, b_t, c_t = sum |r_t|^2);
//   3. candidate c solves its columns' part of A dx = -b (all non-joint-error columns and its terms'
//      coefficients; a pseudo-inverse of the scaled matrix with relative eigenvalue cut 1e-12, where the
//      identifiability analysis of error_model.h draws its line), and its held-out mean square is
//      (c_t + 2 dx^T b_t + dx^T A_t dx) / rows: the linearised prediction of the block.
// The fold's RMS is the square root, per session, averaged over the sessions of the block: sessions weigh
// alike, so that the few rows that re-register the base of a new campaign (the ones that show how the
// model carries over to it) count as much as the campaign it was fitted on. A candidate's CV RMS is the mean of its K
// fold RMS and se their standard deviation over sqrt(K). The simplest candidate whose CV RMS is within one se of the
// best (ESL 7.10's one-standard-error rule) is then fitted by the estimator on all training rows, from the start robot
// with that candidate's terms: the identified robot holds only the chosen terms. Deterministic: no randomness, folds
// from the row order.
// The same held-out predictions of the chosen candidate also give the model-inadequacy tau of its predicted
// sd (estimators/error_model/prediction_uncertainty.h (2), (3)), in the report's prediction_covariance;
// `cross_validate: true` without `select` runs these folds for the fitted model alone, for tau only.
// Priors: the folds' geometry fits and the final fit are maximum a posteriori with the default priors
// (error_model_problem.h, PriorOptions) unless the options give `prior` (on, a map, or `off` for least
// squares); the candidates' one-step scores use the data's normal equations only. Least-squares fits
// chosen the same way can hold out above geometry alone on real data (ur10_ipa2021 series B, README "Real
// data"): cross-validation rates terms the training poses leave loose, and the prior keeps them near
// their start there.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/dataset.h"
#include "framework/registry.h"
#include "robot/robot.h"

namespace kincal {

struct ModelSelectionOptions {
  bool select = false;  // key `select`
  int folds = 5;        // key `select_folds`: K, >= 2
  // key `cross_validate`: without `select`, the same blocked CV for the fitted model alone, for the
  // model-inadequacy tau of the predicted sd (prediction_uncertainty.h (3)); `select` always measures it.
  bool cross_validate = false;

  // Keys select, select_folds.
  static const OptionTable<ModelSelectionOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct SelectionCandidate {
  std::string name;        // "geometry", "+ gravity 2", "+ harmonic 1", ...
  std::vector<int> terms;  // indices into start.joint_errors.terms, in file order
};
// The nested candidates of `start` (see above); the first is geometry, the last the full file.
std::vector<SelectionCandidate> NestedCandidates(const Robot& start);
// `start` with only the candidate's joint-error terms.
Robot CandidateRobot(const Robot& start, const SelectionCandidate& candidate);

// The fold of every row (0..K-1): contiguous blocks within each session (see above).
std::vector<int> BlockedFolds(const Dataset& data, int folds);

struct CandidateScore {
  std::string name;
  int num_parameters = 0;        // free parameters of the candidate's fit
  std::vector<double> fold_rms;  // m, one per fold
  double cv_rms = 0.0;           // m: mean of fold_rms
  double se = 0.0;               // m: standard deviation of fold_rms / sqrt(K)
  // m, the chosen candidate's only (0 and empty for the others): tau of prediction_uncertainty.h (3) from
  // the same held-out rows: rows within the fold's training joint range, and per joint j, rows with joint j
  // beyond it.
  double inadequacy = 0.0;
  std::vector<double> inadequacy_beyond;
  bool chosen = false;
};
// Index of the simplest candidate within one se of the best; candidates in order of complexity.
int OneStandardErrorChoice(const std::vector<CandidateScore>& scores);

// The table as JSON (details.selection of the report: folds, rule, candidates with cv_rms_mm, se_mm,
// fold_rms_mm, parameters, chosen) and as text for a terminal (one line per candidate; with the audit's
// held-out columns and summary line when the table has them, selection_audit.h).
nlohmann::json SelectionToJson(const std::vector<CandidateScore>& scores, int folds);
std::string SelectionTable(const nlohmann::json& selection);
// The chosen candidate's name in that table; "" when none is chosen.
std::string ChosenCandidate(const nlohmann::json& selection);

}  // namespace kincal
