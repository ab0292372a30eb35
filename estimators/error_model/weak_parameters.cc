#include "estimators/error_model/weak_parameters.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include <Eigen/Eigenvalues>

namespace kincal {
namespace {

std::string Sci(double v) {
  if (!std::isfinite(v)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2g", v);
  return buf;
}

}  // namespace

std::string WeakParameter::Describe() const {
  std::string s =
      name + " (data sd " + Sci(data_sd) + " against " + (has_prior ? "its prior " : "") + Sci(reference_sd);
  if (!trades_against.empty()) {
    s += "; trades against";
    for (size_t i = 0; i < trades_against.size(); ++i) s += (i ? ", " : " ") + trades_against[i];
  }
  return s + ")";
}

Eigen::VectorXd DataStddev(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data, double sigma,
                           const std::vector<int>& subset_in, std::vector<std::vector<std::string>>* trades) {
  std::vector<int> subset = subset_in;
  if (subset.empty()) {
    subset.resize(problem.num_parameters());
    std::iota(subset.begin(), subset.end(), 0);
  }
  const int p = static_cast<int>(subset.size());
  Eigen::MatrixXd N(p, p);
  for (int i = 0; i < p; ++i) {
    for (int j = 0; j < p; ++j) N(i, j) = JtJ_data(subset[i], subset[j]);
  }
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd sd = Eigen::VectorXd::Constant(p, inf);
  if (trades) trades->assign(p, {});
  if (p == 0) return sd;
  // Column-normalised: S = D N D, D = 1 / sqrt(diag N), so that units do not decide the eigenvectors.
  Eigen::VectorXd d = N.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int i = 0; i < p; ++i) d[i] = d[i] > 0.0 ? 1.0 / d[i] : 0.0;
  const Eigen::MatrixXd S = d.asDiagonal() * N * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) return sd;
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const Eigen::MatrixXd& V = eig.eigenvectors();
  // Below this eigenvalue a direction is not determined by the data; a parameter takes part in it when
  // its component exceeds 1e-3 (smaller ones are rounding of an unrelated direction).
  const double floor = 1e-12 * std::max(lambda.maxCoeff(), 0.0);
  const std::vector<ErrorModelParameter>& ps = problem.parameters();
  for (int i = 0; i < p; ++i) {
    if (!(d[i] > 0.0)) continue;
    double var = 0.0, worst = -1.0;
    int worst_k = -1;
    for (int k = 0; k < p; ++k) {
      const double share = V(i, k) * V(i, k);
      const double contribution = lambda[k] > floor ? share / lambda[k] : (share > 1e-6 ? inf : 0.0);
      var += contribution;
      if (contribution > worst) {
        worst = contribution;
        worst_k = k;
      }
    }
    sd[i] = sigma * d[i] * std::sqrt(var);
    if (!trades || worst_k < 0) continue;
    std::vector<int> order(p);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return std::abs(V(a, worst_k)) > std::abs(V(b, worst_k)); });
    const double top = std::abs(V(order[0], worst_k));
    for (int o : order) {
      if (o == i) continue;
      if ((*trades)[i].size() >= 4 || std::abs(V(o, worst_k)) < 0.2 * top) break;
      (*trades)[i].push_back(ps[subset[o]].name);
    }
  }
  return sd;
}

std::vector<WeakParameter> FindWeakParameters(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data,
                                              double sigma, const std::vector<int>& subset_in) {
  std::vector<int> subset = subset_in;
  if (subset.empty()) {
    subset.resize(problem.num_parameters());
    std::iota(subset.begin(), subset.end(), 0);
  }
  std::vector<std::vector<std::string>> trades;
  const Eigen::VectorXd sd = DataStddev(problem, JtJ_data, sigma, subset, &trades);
  std::vector<WeakParameter> out;
  for (size_t i = 0; i < subset.size(); ++i) {
    const ErrorModelParameter& q = problem.parameters()[subset[i]];
    if (!(q.reference_sd > 0.0) || !(sd[i] > q.reference_sd)) continue;
    WeakParameter w;
    w.name = q.name;
    w.data_sd = sd[i];
    w.reference_sd = q.reference_sd;
    w.has_prior = q.prior_sd > 0.0;
    w.trades_against = trades[i];
    out.push_back(w);
  }
  return out;
}

std::vector<int> ChooseWeakToHold(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data, double sigma,
                                  std::vector<WeakParameter>* weak) {
  std::vector<int> active(problem.num_parameters());
  std::iota(active.begin(), active.end(), 0);
  *weak = FindWeakParameters(problem, JtJ_data, sigma, active);
  std::vector<int> hold;
  while (!active.empty()) {
    const Eigen::VectorXd sd = DataStddev(problem, JtJ_data, sigma, active);
    int pick = -1;
    double worst = 1.0;
    for (size_t i = 0; i < active.size(); ++i) {
      const ErrorModelParameter& q = problem.parameters()[active[i]];
      if (q.prior_sd > 0.0 || !(q.reference_sd > 0.0)) continue;
      const double ratio = sd[i] / q.reference_sd;
      if (ratio > worst) {
        worst = ratio;
        pick = static_cast<int>(i);
      }
    }
    if (pick < 0) break;
    hold.push_back(active[pick]);
    for (auto& w : *weak) w.held = w.held || w.name == problem.parameters()[active[pick]].name;
    active.erase(active.begin() + pick);
  }
  // Without a prior, what holding the others determined is no longer weak.
  weak->erase(
      std::remove_if(weak->begin(), weak->end(), [](const WeakParameter& w) { return !w.held && !w.has_prior; }),
      weak->end());
  return hold;
}

}  // namespace kincal
