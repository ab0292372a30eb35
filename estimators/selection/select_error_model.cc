#include "estimators/selection/select_error_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <Eigen/Eigenvalues>

#include "estimators/selection/model_selection.h"

namespace kincal {
namespace {

// Held-out position sums of one session in a fold: sum J^T J, J^T r, |r|^2 and the row count.
struct TestSums {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  double c = 0.0;
  int rows = 0;
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
    } else if (n == 3) {  // sizes fixed at compile time: GCC cannot bound a run-time head(n) of a Vector6d
      AddTrainingRow(weighting, i, J.topRows<3>(), r.head<3>(), &s);
    } else {
      AddTrainingRow(weighting, i, J, r, &s);
    }
  }
  return s;
}

// dx over `columns` (zero elsewhere) solving A dx = -b there: pseudo-inverse of the scaled matrix.
Eigen::VectorXd GaussNewtonStep(const FoldSums& s, const std::vector<int>& columns) {
  const int q = static_cast<int>(columns.size());
  Eigen::MatrixXd M(q, q);
  Eigen::VectorXd g(q), d(q);
  for (int a = 0; a < q; ++a) {
    const double diag = s.A(columns[a], columns[a]);
    d[a] = diag > 0.0 ? 1.0 / std::sqrt(diag) : 0.0;
  }
  for (int a = 0; a < q; ++a) {
    g[a] = d[a] * s.b[columns[a]];
    for (int c = 0; c < q; ++c) M(a, c) = d[a] * s.A(columns[a], columns[c]) * d[c];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double cut = 1e-12 * std::max(lambda.maxCoeff(), 0.0);
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(q);
  for (int a = 0; a < q; ++a)
    if (lambda[a] > cut && lambda[a] > 0.0) inv[a] = 1.0 / lambda[a];
  const Eigen::VectorXd y = -(eig.eigenvectors() * (inv.asDiagonal() * (eig.eigenvectors().transpose() * g)));
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(s.A.rows());
  for (int a = 0; a < q; ++a) dx[columns[a]] = d[a] * y[a];
  return dx;
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

}  // namespace

void SelectErrorModel(const std::string& estimator, const ErrorModelEstimatorOptions& options, int budget,
                      const ErrorModelMinimizer& minimize, const Robot& start, const Robot& controller,
                      const Dataset& data, Robot* identified, EstimationReport* report) {
  const int K = options.selection.folds;
  ErrorModelEstimatorOptions fit_options = options;
  fit_options.selection.select = false;
  // Maximum a posteriori with the default priors unless the options say `prior` (model_selection.h).
  if (!fit_options.error_model.prior.given) fit_options.error_model.prior.enabled = true;
  const std::vector<SelectionCandidate> candidates = NestedCandidates(start);
  const std::vector<int> fold = BlockedFolds(data, K);
  const RowWeighting weighting = options.weighting.Weighting(data.rows.size(), estimator);
  const Robot geometry = CandidateRobot(start, candidates[0]);

  std::vector<CandidateScore> scores(candidates.size());
  for (size_t c = 0; c < candidates.size(); ++c) scores[c].name = candidates[c].name;
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
    if (!options.weighting.weights.empty()) {
      fold_options.weighting.weights.clear();
      for (int i : train_rows) fold_options.weighting.weights.push_back(options.weighting.weights[i]);
    }
    const Dataset train = data.SelectRows(train_rows);
    Robot fitted;
    EstimationReport fold_report;
    EstimateErrorModel(estimator, fold_options, budget, minimize, geometry, controller, train, &fitted, &fold_report);
    Robot point = fitted;  // the fold's geometry fit with every term of the file at its start value
    point.joint_errors = start.joint_errors;
    const ErrorModelProblem problem(point, controller, data, fit_options.error_model);
    const FoldSums sums = AccumulateFold(problem, weighting, fold, k, sessions);
    const std::vector<int> column_term = ColumnTerms(problem);
    for (size_t c = 0; c < candidates.size(); ++c) {
      std::vector<int> columns;
      const std::set<int> terms(candidates[c].terms.begin(), candidates[c].terms.end());
      for (size_t j = 0; j < column_term.size(); ++j) {
        if (column_term[j] < 0 || terms.count(column_term[j])) columns.push_back(static_cast<int>(j));
      }
      const Eigen::VectorXd dx = GaussNewtonStep(sums, columns);
      double rms = 0.0;  // sessions weigh alike (model_selection.h)
      for (const auto& [session, t] : sums.test) rms += t.Rms(dx) / sums.test.size();
      scores[c].fold_rms.push_back(rms);
      scores[c].num_parameters = static_cast<int>(columns.size());
    }
  }
  for (auto& s : scores) {
    double mean = 0.0, var = 0.0;
    for (double r : s.fold_rms) mean += r / K;
    for (double r : s.fold_rms) var += (r - mean) * (r - mean) / (K - 1);
    s.cv_rms = mean;
    s.se = std::sqrt(var / K);
  }
  const int chosen = OneStandardErrorChoice(scores);
  scores[chosen].chosen = true;

  EstimateErrorModel(estimator, fit_options, budget, minimize, CandidateRobot(start, candidates[chosen]), controller,
                     data, identified, report);
  report->details["selection"] = SelectionToJson(scores, K);
  report->message += "; selected model: " + candidates[chosen].name;
}

}  // namespace kincal
