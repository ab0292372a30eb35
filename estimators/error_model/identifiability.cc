#include "estimators/error_model/identifiability.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;

int Priority(Group g) {
  switch (g) {
    // Fixtures before the base: distances from unknown pivots or contacts with an unknown plane see the
    // arm relative to them, so the base is what the data cannot see (a pivot's frame is not the arm's).
    case Group::kFixture:
      return -1;
    case Group::kBase:
      return 0;
    case Group::kSession:
      return 1;
    case Group::kMarker:
      return 2;
    case Group::kTool:
      return 3;
    case Group::kRatio:
      return 4;
    // Joint error coefficients before the link geometry: a frame's own angle (theta_6 beside a marker
    // off the flange) is redundant with the tool once the gravity moments of that link re-mix, and must
    // not become "identifiable" through that re-mixing alone; the coefficients it would displace are not.
    case Group::kJointError:
      return 5;
    case Group::kJoint:
      return 6;
  }
  return 7;
}

// Singular values (descending) of a matrix A given A^T A.
Eigen::VectorXd SingularValuesFromGram(const Eigen::MatrixXd& G) {
  if (G.rows() == 0) return Eigen::VectorXd();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G, Eigen::EigenvaluesOnly);
  const Eigen::VectorXd ascending = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return ascending.reverse();
}

}  // namespace

ObservabilityIndices ComputeObservabilityIndices(const Eigen::VectorXd& s, int num_rows) {
  ObservabilityIndices o;
  const int L = static_cast<int>(s.size());
  if (L == 0 || num_rows <= 0) return o;
  const double s_min = s[L - 1], s_max = s[0];
  double log_sum = 0.0, inverse_sum = 0.0;
  for (int i = 0; i < L; ++i) {
    log_sum += std::log(s[i]);
    inverse_sum += 1.0 / s[i];
  }
  o.o1 = std::exp(log_sum / L) / std::sqrt(static_cast<double>(num_rows));
  o.o2 = s_min / s_max;
  o.o3 = s_min;
  o.o4 = s_min * s_min / s_max;
  o.o5 = 1.0 / inverse_sum;
  return o;
}

namespace {

// Columns whose effect on the measurements (norm times characteristic scale) is below 1e-3 tolerance of the
// largest: they are held for having none.
std::vector<bool> NoEffect(const Eigen::VectorXd& norms, const Eigen::VectorXd& scale, double tolerance) {
  const int p = static_cast<int>(norms.size());
  double max_effect = 0.0;
  for (int j = 0; j < p; ++j) max_effect = std::max(max_effect, norms[j] * scale[j]);
  std::vector<bool> no_effect(p);
  for (int j = 0; j < p; ++j) no_effect[j] = !(norms[j] * scale[j] > 1e-3 * tolerance * max_effect);
  return no_effect;
}

// The columns kept by a right-looking Cholesky of the column-normalised Gram matrix in the groups' priority
// order: a column whose pivot (its part not spanned by the columns kept before it) is at most tolerance^2
// is held; columns without effect are skipped.
std::vector<bool> KeptColumns(const std::vector<ErrorModelParameter>& params, const Eigen::MatrixXd& JtJ,
                              const Eigen::VectorXd& norms, const std::vector<bool>& no_effect, double tolerance) {
  const int p = static_cast<int>(params.size());
  std::vector<int> order(p);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return Priority(params[a].group) < Priority(params[b].group); });
  Eigen::MatrixXd W(p, p);
  for (int a = 0; a < p; ++a) {
    for (int b = 0; b < p; ++b) {
      W(a, b) = (no_effect[a] || no_effect[b]) ? 0.0 : JtJ(a, b) / (norms[a] * norms[b]);
    }
  }
  const double threshold = tolerance * tolerance;
  std::vector<bool> keep(p, false);
  for (int k = 0; k < p; ++k) {
    const int c = order[k];
    if (no_effect[c]) continue;
    const double d = W(c, c);
    if (!(d > threshold)) continue;
    keep[c] = true;
    const double pivot = std::sqrt(d);
    for (int a = k + 1; a < p; ++a) {
      const int i = order[a];
      if (no_effect[i]) continue;
      const double li = W(i, c) / pivot;
      for (int b = k + 1; b < p; ++b) {
        const int j = order[b];
        if (!no_effect[j]) W(i, j) -= li * W(j, c) / pivot;
      }
    }
  }
  return keep;
}

// The held columns with their reasons: a held column is (nearly) a combination of kept ones, so the kept
// parameters that carry most of it are named, from the least-squares coefficients beta = S_KK^-1 S_Kj of
// the scaled Gram matrix.
void NameHeld(const std::vector<ErrorModelParameter>& params, const Eigen::MatrixXd& JtJ, const Eigen::VectorXd& norms,
              const std::vector<bool>& no_effect, const std::vector<bool>& keep, IdentifiabilityAnalysis* out) {
  const int p = static_cast<int>(params.size());
  const int L = static_cast<int>(out->identifiable.size());
  Eigen::MatrixXd S_kept(L, L);
  for (int a = 0; a < L; ++a) {
    for (int b = 0; b < L; ++b) {
      const int i = out->identifiable[a], j = out->identifiable[b];
      S_kept(a, b) = JtJ(i, j) / (norms[i] * norms[j]);
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S_kept);
  for (int j = 0; j < p; ++j) {
    if (keep[j]) continue;
    out->unidentifiable.push_back(j);
    out->unidentifiable_names.push_back(params[j].name);
    if (no_effect[j] || L == 0) {
      out->reasons.push_back("not identifiable: no effect on the measurements");
      continue;
    }
    Eigen::VectorXd column(L);
    for (int a = 0; a < L; ++a) column[a] = JtJ(out->identifiable[a], j) / (norms[out->identifiable[a]] * norms[j]);
    const Eigen::VectorXd beta = ldlt.solve(column);
    std::vector<int> order_by_weight(L);
    std::iota(order_by_weight.begin(), order_by_weight.end(), 0);
    std::stable_sort(order_by_weight.begin(), order_by_weight.end(),
                     [&](int a, int b) { return std::abs(beta[a]) > std::abs(beta[b]); });
    std::string with;
    for (int k = 0; k < std::min(L, 4); ++k) {
      const int a = order_by_weight[k];
      if (!(std::abs(beta[a]) >= 0.1 * std::abs(beta[order_by_weight[0]]))) break;
      with += (with.empty() ? "" : ", ") + params[out->identifiable[a]].name;
    }
    out->reasons.push_back("not identifiable: redundant with " + with);
  }
}

// The kept columns' singular values (column-normalised and in characteristic units), condition number and
// observability indices.
void Spectra(const Eigen::MatrixXd& JtJ, const Eigen::VectorXd& norms, const Eigen::VectorXd& scale, int num_rows,
             IdentifiabilityAnalysis* out) {
  const int L = static_cast<int>(out->identifiable.size());
  Eigen::MatrixXd S(L, L), C(L, L);
  for (int a = 0; a < L; ++a) {
    for (int b = 0; b < L; ++b) {
      const int i = out->identifiable[a], j = out->identifiable[b];
      S(a, b) = JtJ(i, j) / (norms[i] * norms[j]);
      C(a, b) = JtJ(i, j) * scale[i] * scale[j];
    }
  }
  out->singular_values = SingularValuesFromGram(S);
  out->characteristic_singular_values = SingularValuesFromGram(C);
  out->condition_number = L > 0 ? out->singular_values[0] / out->singular_values[L - 1] : 1.0;
  out->observability = ComputeObservabilityIndices(out->characteristic_singular_values, num_rows);
}

}  // namespace

IdentifiabilityAnalysis AnalyzeIdentifiability(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ,
                                               int num_rows, double tolerance) {
  const int p = problem.num_parameters();
  const std::vector<ErrorModelParameter>& params = problem.parameters();
  const Eigen::VectorXd scale = problem.CharacteristicScales();
  const Eigen::VectorXd norms = JtJ.diagonal().cwiseMax(0.0).cwiseSqrt();
  const std::vector<bool> no_effect = NoEffect(norms, scale, tolerance);
  const std::vector<bool> keep = KeptColumns(params, JtJ, norms, no_effect, tolerance);
  IdentifiabilityAnalysis out;
  for (int j = 0; j < p; ++j) {
    if (keep[j]) out.identifiable.push_back(j);
  }
  NameHeld(params, JtJ, norms, no_effect, keep, &out);
  out.rank = static_cast<int>(out.identifiable.size());
  Spectra(JtJ, norms, scale, num_rows, &out);
  return out;
}

}  // namespace kincal
