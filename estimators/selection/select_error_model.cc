#include "estimators/selection/select_error_model.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "estimators/error_model/covariance.h"
#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/error_model/prior_factor.h"
#include "estimators/selection/model_selection.h"

namespace kincal {
namespace {

// Held-out position sums of one session in a fold: sum J^T J, J^T r, |r|^2 and the row count.
struct TestSums {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  double c = 0.0;
  int rows = 0;
  // Per row, for prediction_uncertainty.h (3): position Jacobian, residual, and the joints whose reading lies
  // beyond the fold's training range (PredictionCovariance::kJointMargin).
  std::vector<Eigen::MatrixXd> J;
  std::vector<Eigen::Vector3d> r;
  std::vector<std::vector<int>> beyond;
  // RMS of the held-out positions after the step dx (linearised).
  double Rms(const Eigen::VectorXd& dx) const {
    const double ms = (c + 2.0 * dx.dot(b) + dx.dot(A * dx)) / std::max(1, rows);
    return std::sqrt(std::max(ms, 0.0));
  }
};

// Sums of one fold at the geometry fit: training normal equations, held-out sums per session.
struct FoldSums {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  // The same with the priors' terms (the problem's PriorFactors; equal to A, b without priors): the
  // candidates' steps solve these, as the estimator's maximum a posteriori fit does.
  Eigen::MatrixXd A_map;
  Eigen::VectorXd b_map;
  double c = 0.0;     // sum w |r|^2 of the training rows (the sigma^2 of normal_equations.h's irls_squares)
  int residuals = 0;  // of the training rows with a positive weight
  std::map<int, TestSums> test;
};

// Adds row i (residuals r, Jacobian J, weighted and robustified) to the fold's normal equations.
template <typename JacobianRows, typename Residuals>
void AddTrainingRow(const RowWeighting& weighting, int i, const JacobianRows& J, const Residuals& r, FoldSums* s) {
  double rho = 0.0, rho_prime = 1.0;
  weighting.loss.Evaluate(r.squaredNorm(), &rho, &rho_prime);
  const double w = weighting.weight(i) * rho_prime;
  if (w <= 0.0) return;
  s->A.noalias() += w * J.transpose() * J;
  s->b.noalias() += w * J.transpose() * r;
  s->c += w * r.squaredNorm();
  s->residuals += static_cast<int>(r.size());
}

FoldSums AccumulateFold(const ErrorModelProblem& problem, const RowWeighting& weighting, const std::vector<int>& fold,
                        int k, const std::set<int>& registered_sessions) {
  const int p = problem.num_parameters();
  FoldSums s;
  s.A = Eigen::MatrixXd::Zero(p, p);
  s.b = Eigen::VectorXd::Zero(p);
  const Eigen::VectorXd x = problem.InitialX();
  auto ws = problem.NewWorkspace();
  Vector6d r;
  Matrix6Xd J;
  const Dataset& data = problem.data();
  Eigen::VectorXd q_min, q_max;  // the fold's training range per joint
  for (int i = 0; i < problem.num_rows(); ++i) {
    if (fold[i] == k) continue;
    const Eigen::VectorXd& q = data.rows[i].q;
    if (q_min.size() == 0) q_min = q_max = q;
    else if (q.size() == q_min.size()) q_min = q_min.cwiseMin(q), q_max = q_max.cwiseMax(q);
  }
  const auto beyond = [&](const Eigen::VectorXd& q) {
    std::vector<int> joints;
    const double m = PredictionCovariance::kJointMargin;
    for (Eigen::Index j = 0; j < q.size() && q.size() == q_min.size(); ++j)
      if (q[j] - q_max[j] > m || q_min[j] - q[j] > m) joints.push_back(static_cast<int>(j));
    return joints;
  };
  for (int i = 0; i < problem.num_rows(); ++i) {
    const bool test = fold[i] == k;
    if (test && !registered_sessions.count(data.rows[i].session)) continue;  // no base for it in this fold
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, &J);
    if (test) {
      const Eigen::MatrixXd Jp = J.topRows(3);
      const Eigen::Vector3d rp(r[0], r[1], r[2]);
      TestSums& t = s.test[data.rows[i].session];
      if (t.rows == 0) t.A = Eigen::MatrixXd::Zero(p, p), t.b = Eigen::VectorXd::Zero(p);
      t.A.noalias() += Jp.transpose() * Jp;
      t.b.noalias() += Jp.transpose() * rp;
      t.c += rp.squaredNorm();
      ++t.rows;
      t.J.push_back(Jp);
      t.r.push_back(rp);
      t.beyond.push_back(beyond(data.rows[i].q));
    } else if (n == 3) {  // sizes fixed at compile time: GCC cannot bound a run-time head(n) of a Vector6d
      AddTrainingRow(weighting, i, J.topRows<3>(), r.head<3>(), &s);
    } else {
      AddTrainingRow(weighting, i, J, r, &s);
    }
  }
  s.A_map = s.A;
  s.b_map = s.b;
  for (const PriorFactor& f : PriorFactors(problem)) {
    const double w = f.scale * f.scale;
    s.A_map(f.index, f.index) += w;
    s.b_map[f.index] += w * (x[f.index] - f.mean);
  }
  return s;
}

// dx over `columns` (zero elsewhere) solving A_map dx = -b_map there: pseudo-inverse of the scaled matrix.
Eigen::VectorXd GaussNewtonStep(const FoldSums& s, const std::vector<int>& columns) {
  const int q = static_cast<int>(columns.size());
  const Eigen::MatrixXd P = ScaledPseudoInverse(s.A_map, columns);
  Eigen::VectorXd g(q);
  for (int a = 0; a < q; ++a) g[a] = s.b_map[columns[a]];
  const Eigen::VectorXd y = -(P * g);
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(s.A.rows());
  for (int a = 0; a < q; ++a) dx[columns[a]] = y[a];
  return dx;
}

// prediction_uncertainty.h (3), one fold and candidate: per held-out row, |e|^2 after the step dx (the
// linearised prediction the candidate's CV RMS is made of) and its expectation under the bound,
// 3 sigma_k^2 + sd_k^2, with sigma_k from the training rows' data sums at dx and C_k = sigma_k^2 A_map^+
// over `columns`: the covariance of that same step (the posterior's where the fit has priors). Data-only
// covariances beside a prior-held step, or the reverse, belong to another estimate than e's (measured:
// ur10_ipa2021 series D, a data-only step beside priors' sd predicted rows beyond the fold's joint-4
// range 0.1 m off with an sd of 7 mm, tau 45 mm).
void FoldExcess(const FoldSums& s, const std::vector<int>& columns, const Eigen::VectorXd& dx,
                InadequacySample* out) {
  const int q = static_cast<int>(columns.size());
  if (s.residuals <= q) return;
  const double sigma2 = std::max(s.c + 2.0 * dx.dot(s.b) + dx.dot(s.A * dx), 0.0) / (s.residuals - q);
  const Eigen::MatrixXd C = sigma2 * ScaledPseudoInverse(s.A_map, columns);
  Eigen::MatrixXd Jc(3, q);
  for (const auto& [session, t] : s.test) {
    for (size_t i = 0; i < t.J.size(); ++i) {
      for (int a = 0; a < q; ++a) Jc.col(a) = t.J[i].col(columns[a]);
      out->squared_error.push_back((t.r[i] + t.J[i] * dx).squaredNorm());  // linearised, as the fold's RMS
      out->expected.push_back(3.0 * sigma2 + (Jc * C * Jc.transpose()).trace());
      out->beyond.push_back(t.beyond[i]);
    }
  }
}

// Per problem column: the joint-error term it belongs to, -1 for every other parameter.
std::vector<int> ColumnTerms(const ErrorModelProblem& problem) {
  std::vector<int> coefficient_term;
  const auto& terms = problem.start().joint_errors.terms;
  for (size_t t = 0; t < terms.size(); ++t)
    coefficient_term.insert(coefficient_term.end(), terms[t].coefficients.size(), static_cast<int>(t));
  std::vector<int> out;
  for (const auto& p : problem.parameters()) {
    out.push_back(p.group == ErrorModelParameter::Group::kJointError ? coefficient_term.at(p.coefficient) : -1);
  }
  return out;
}

// Per problem column: whether the fold's own fit held that parameter (its identifiability analysis or weak
// hold: what the fold's rows cannot fix); the candidates' steps hold it too.
std::vector<bool> FoldHeld(const ErrorModelProblem& problem, const EstimationReport& fold_report) {
  std::set<std::string> names;
  if (fold_report.details.contains("held_parameters")) {
    for (const auto& h : fold_report.details.at("held_parameters")) names.insert(h.value("name", std::string()));
  }
  std::vector<bool> out;
  for (const auto& p : problem.parameters()) out.push_back(names.count(p.name) > 0);
  return out;
}

// The noise that weighed the fold's priors (m; 0 without priors): its fit's, so that the candidates' steps
// weigh data and priors as that fit did.
double FoldPriorNoise(const EstimationReport& fold_report) {
  const nlohmann::json& d = fold_report.details;
  return d.contains("prior_noise_m") && d.at("prior_noise_m").is_number() ? d.at("prior_noise_m").get<double>() : 0.0;
}

// Blocked K-fold CV of `candidates` (column sets of `start`'s problem): per fold, `fold_start` fitted on the
// other blocks, then each candidate one Gauss-Newton step from there (model_selection.h; `step` false: the
// fold's fit itself, for the fitted model alone), its held-out RMS and its rows of prediction_uncertainty.h
// (3) for the candidate `choose` picks from the scores (only that one: (3) needs every held-out row's sd
// under the candidate's covariance, 3 q^2 per row, which for all 23 candidates of ur10_ipa2021 series A
// took longer than the selection itself). Scores with fold_rms, cv_rms, se; the chosen one with inadequacy
// and inadequacy_beyond; returns the chosen index.
using Choice = std::function<int(std::vector<CandidateScore>*)>;
int CrossValidate(const std::string& estimator, const ErrorModelEstimatorOptions& fit_options, int budget,
                  const ErrorModelMinimizer& minimize, const Robot& fold_start, const Robot& start,
                  const Robot& controller, const Dataset& data, const std::vector<SelectionCandidate>& candidates,
                  bool step, const Choice& choose, std::vector<CandidateScore>* out) {
  std::vector<CandidateScore>& scores = *out;
  const int K = fit_options.selection.folds;
  const std::vector<int> fold = BlockedFolds(data, K);
  const RowWeighting weighting = fit_options.weighting.Weighting(data.rows.size(), estimator);
  scores.assign(candidates.size(), CandidateScore());
  for (size_t c = 0; c < candidates.size(); ++c) scores[c].name = candidates[c].name;
  // Each fold's sums and, per candidate, its columns and step: kept for (3) of the chosen one.
  std::vector<FoldSums> fold_sums;
  std::vector<std::vector<std::vector<int>>> fold_columns;
  std::vector<std::vector<Eigen::VectorXd>> fold_steps;
  // The priors' means: the start's values, as in the estimator's fit (the folds' problems start elsewhere).
  const ErrorModelProblem reference(start, controller, data, fit_options.error_model);
  for (int k = 0; k < K; ++k) {
    std::vector<int> train_rows;
    std::set<int> sessions;
    for (size_t i = 0; i < data.rows.size(); ++i) {
      if (fold[i] != k) {
        train_rows.push_back(static_cast<int>(i));
        sessions.insert(data.rows[i].session);
      }
    }
    ErrorModelEstimatorOptions fold_options = fit_options;
    if (!fit_options.weighting.weights.empty()) {
      fold_options.weighting.weights.clear();
      for (int i : train_rows) fold_options.weighting.weights.push_back(fit_options.weighting.weights[i]);
    }
    const Dataset train = data.SelectRows(train_rows);
    Robot fitted;
    EstimationReport fold_report;
    EstimateErrorModel(estimator, fold_options, budget, minimize, fold_start, controller, train, &fitted, &fold_report);
    Robot point = fitted;  // the fold's fit with every term of `start` (at its start value where not fitted)
    if (fitted.joint_errors.terms.size() != start.joint_errors.terms.size()) point.joint_errors = start.joint_errors;
    ErrorModelProblem problem(point, controller, data, fit_options.error_model);
    problem.InheritPriors(reference);
    problem.set_prior_noise(FoldPriorNoise(fold_report));
    fold_sums.push_back(AccumulateFold(problem, weighting, fold, k, sessions));
    fold_columns.emplace_back();
    fold_steps.emplace_back();
    const FoldSums& sums = fold_sums.back();
    const std::vector<int> column_term = ColumnTerms(problem);
    const std::vector<bool> held = FoldHeld(problem, fold_report);
    for (size_t c = 0; c < candidates.size(); ++c) {
      std::vector<int> columns;
      const std::set<int> terms(candidates[c].terms.begin(), candidates[c].terms.end());
      const std::set<std::string> held_terms(candidates[c].held.begin(), candidates[c].held.end());
      for (size_t j = 0; j < column_term.size(); ++j) {
        const bool in = column_term[j] < 0 || (terms.count(column_term[j]) && !held_terms.count(problem.parameters()[j].name));
        if (in && !held[j]) columns.push_back(static_cast<int>(j));
      }
      const Eigen::VectorXd dx = step ? GaussNewtonStep(sums, columns) : Eigen::VectorXd::Zero(sums.A.rows());
      double rms = 0.0;  // sessions weigh alike (model_selection.h)
      for (const auto& [session, t] : sums.test) rms += t.Rms(dx) / sums.test.size();
      scores[c].fold_rms.push_back(rms);
      scores[c].num_parameters = static_cast<int>(columns.size());
      fold_columns.back().push_back(std::move(columns));
      fold_steps.back().push_back(dx);
    }
  }
  for (CandidateScore& s : scores) {
    double mean = 0.0, var = 0.0;
    for (double r : s.fold_rms) mean += r / K;
    for (double r : s.fold_rms) var += (r - mean) * (r - mean) / (K - 1);
    s.cv_rms = mean;
    s.se = std::sqrt(var / K);
  }
  const int chosen = choose(&scores);
  InadequacySample sample;
  for (int k = 0; k < K; ++k) FoldExcess(fold_sums[k], fold_columns[k][chosen], fold_steps[k][chosen], &sample);
  scores[chosen].chosen = true;
  scores[chosen].inadequacy = EstimateInadequacy(sample, -1);
  for (int j = 0; j < start.dof(); ++j) scores[chosen].inadequacy_beyond.push_back(EstimateInadequacy(sample, j));
  return chosen;
}

// Writes tau into the report's prediction_covariance (prediction_uncertainty.h (2)).
void SetInadequacy(const CandidateScore& score, const std::string& source, EstimationReport* report) {
  if (!report->details.contains("prediction_covariance")) return;
  nlohmann::json& c = report->details["prediction_covariance"];
  c["inadequacy_m"] = score.inadequacy;
  c["inadequacy_beyond_m"] = score.inadequacy_beyond;  // per joint
  c["inadequacy_source"] = source;
}

}  // namespace

void SelectErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                      const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                      const Dataset& data, Robot* identified, EstimationReport* report) {
  const int K = options.selection.folds;
  ErrorModelEstimatorOptions fit_options = options;
  // Maximum a posteriori with the default priors unless the options say `prior` (model_selection.h).
  if (!fit_options.error_model.prior.given) fit_options.error_model.prior.enabled = true;
  const std::vector<SelectionCandidate> candidates = NestedCandidates(start);
  std::vector<CandidateScore> scores;
  const int chosen = CrossValidate(estimator, fit_options, budget, minimize, CandidateRobot(start, candidates[0]),
                                   start, controller, data, candidates, true, PairedStandardErrorChoice, &scores);

  ErrorModelEstimatorOptions chosen_options = fit_options;
  auto& fixed = chosen_options.error_model.fixed;
  fixed.insert(fixed.end(), candidates[chosen].held.begin(), candidates[chosen].held.end());
  EstimateErrorModel(estimator, chosen_options, budget, minimize, CandidateRobot(start, candidates[chosen]), controller,
                     data, identified, report);
  report->details["selection"] = SelectionToJson(scores, K);
  report->message += "; selected model: " + candidates[chosen].name;
  SetInadequacy(scores[chosen], "cross-validation of the selection", report);
}

void CrossValidateErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                             const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                             const Dataset& data, EstimationReport* report) {
  SelectionCandidate whole;
  whole.name = "fitted model";
  for (size_t t = 0; t < start.joint_errors.terms.size(); ++t) whole.terms.push_back(static_cast<int>(t));
  std::vector<CandidateScore> scores;
  CrossValidate(estimator, options, budget, minimize, start, start, controller, data, {whole}, false,
                [](std::vector<CandidateScore>*) { return 0; }, &scores);
  nlohmann::json cv = SelectionToJson(scores, options.selection.folds);
  cv["rule"] = "the fitted model alone (cross_validate: true)";
  report->details["cross_validation"] = cv;
  SetInadequacy(scores[0], "cross-validation", report);
}

}  // namespace kincal
