#pragma once
// Model selection among nested joint-level error models (option `select: true` of the error-model
// estimators, `kincal identify --select`): which of the robot file's joint-error terms the training data
// support, judged by how well each model predicts rows it was not fitted on.
//
// Candidates (NestedCandidates), nested: geometry only (no joint-error term), then one coefficient of
// compliance per joint with a gravity term ("+ compliance 2", ...: the joint deflects in proportion to the
// gravity torque of a point mass at the last frame's origin, the term's `link<n>` coefficient, its others
// held at their start value), then the file's terms added one group at a time, a group being one type on
// one joint, types in the order gravity (the whole mass-moment term, 12-24 coefficients), harmonic,
// backlash, approach and joints in increasing order within a type (gravity 2, gravity 3, ..., harmonic 1,
// ...), up to the full file. Few rows carry a compliance where they cannot carry a full gravity term. Every
// candidate keeps everything else the estimator frees (geometry, base, tool, ratios, markers, sessions).
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
//   3. candidate c solves its columns' part of (A + P) dx = -(b + P (x - mu)) (all non-joint-error columns
//      and its terms' free coefficients, less what the fold's own fit held: the parameters its
//      identifiability analysis or weak hold found the fold's rows cannot fix; P, mu the priors of the
//      estimator's fit (PriorFactors, with that fit's prior noise), none without priors; a
//      pseudo-inverse of the scaled matrix with relative eigenvalue cut 1e-12, where the
//      identifiability analysis of error_model.h draws its line), and its held-out mean square is
//      (c_t + 2 dx^T b_t + dx^T A_t dx) / rows: the linearised prediction of the block. So the step is one
//      Gauss-Newton step of the fit the estimator makes, priors and holds included, and geometry's score
//      is its fold fit's own prediction: a data-only step moved what the fold's rows barely fix (on
//      ur10_ipa2021 series D the tool's z and a session's x: one fold predicted 53.7 mm where its fit
//      predicts 0.84 mm).
// The fold's RMS is the square root, per session, averaged over the sessions of the block: sessions weigh
// alike, so that the few rows that re-register the base of a new campaign (the ones that show how the
// model carries over to it) count as much as the campaign it was fitted on. A candidate's CV RMS is the mean of its K
// fold RMS and se their standard deviation over sqrt(K). Rule (PairedStandardErrorChoice): the simplest
// candidate whose mean fold-wise excess over the best candidate is within one standard error of that
// excess (ESL 7.10's one-standard-error rule on paired differences, Nadeau and Bengio's corrected se), then
// fitted by the estimator on all training rows, from the start robot with that candidate's terms (a
// compliance candidate's other gravity coefficients held): the identified robot holds only the chosen
// terms. Deterministic: no randomness, folds from the row order.
// The same held-out predictions of the chosen candidate also give the model-inadequacy tau of its predicted
// sd (estimators/error_model/prediction_uncertainty.h (2), (3)), in the report's prediction_covariance;
// `cross_validate: true` without `select` runs these folds for the fitted model alone, for tau only.
// Priors: the folds' geometry fits and the final fit are maximum a posteriori with the default priors
// (error_model_problem.h, PriorOptions) unless the options give `prior` (on, a map, or `off` for least
// squares); the candidates' one-step scores add the same priors (3. above). Least-squares fits
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

  // The keys select, select_folds and cross_validate.
  static const OptionTable<ModelSelectionOptions>& Table();
  bool IsValid(std::string* why) const;
};

struct SelectionCandidate {
  std::string name;        // "geometry", "+ compliance 2", "+ gravity 2", "+ harmonic 1", ...
  std::vector<int> terms;  // indices into start.joint_errors.terms, in file order
  // Coefficients of those terms held at their start value (names as JointErrors::CoefficientNames): a
  // compliance candidate's gravity term frees one coefficient of its joint's term.
  std::vector<std::string> held;
};
// The nested candidates of `start` (see above); the first is geometry, the last the full file.
std::vector<SelectionCandidate> NestedCandidates(const Robot& start);
// The coefficient a compliance candidate frees in a bound gravity term: its `link<n>` key (n the last
// frame), a point mass at the last frame's origin; "" when the term has no such key or nothing else.
std::string ComplianceKey(const JointErrorTerm& term, int dof);
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
  double excess_se = 0.0;        // m: se of the fold-wise excess over the best (PairedStandardErrorChoice)
  // m, the chosen candidate's only (0 and empty for the others): tau of prediction_uncertainty.h (3) from
  // the same held-out rows: rows within the fold's training joint range, and per joint j, rows with joint j
  // beyond it.
  double inadequacy = 0.0;
  std::vector<double> inadequacy_beyond;
  bool chosen = false;
};
// Index of the simplest candidate within one se of the best; candidates in order of complexity.
int OneStandardErrorChoice(const std::vector<CandidateScore>& scores);
// The same rule on paired differences: the simplest candidate whose mean excess over the best candidate's
// fold RMS, fold by fold, is within one standard error of that excess; sets every score's excess_se.
// The folds share their blocks, so what makes one fold hard for every candidate cancels in the
// difference (on a few hundred rows it swamps the se of each CV RMS alone). The se is Nadeau and
// Bengio's corrected resampled one (Machine Learning 52, 2003): var(d) (1/K + n_test/n_train), n_test/n_train
// = 1/(K-1) for K folds, since the folds' training sets overlap.
int PairedStandardErrorChoice(std::vector<CandidateScore>* scores);

// The table as JSON (details.selection of the report: folds, rule, candidates with cv_rms_mm, se_mm,
// fold_rms_mm, parameters, chosen) and as text for a terminal (one line per candidate; with the audit's
// held-out columns and summary line when the table has them, selection_audit.h).
nlohmann::json SelectionToJson(const std::vector<CandidateScore>& scores, int folds);
std::string SelectionTable(const nlohmann::json& selection);
// The chosen candidate's name in that table; "" when none is chosen.
std::string ChosenCandidate(const nlohmann::json& selection);

}  // namespace kincal
