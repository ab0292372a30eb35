#include "estimators/error_model/normal_equations.h"

#include <cmath>
#include <stdexcept>

namespace kincal {

void RobustLoss::Evaluate(double s, double* rho, double* rho_prime, double* rho_second) const {
  const double c2 = scale * scale;
  double second = 0.0;
  switch (type) {
    case Type::kNone:
      *rho = s;
      *rho_prime = 1.0;
      break;
    case Type::kHuber:
      if (s <= c2) {
        *rho = s;
        *rho_prime = 1.0;
      } else {
        const double r = std::sqrt(s);
        *rho = 2.0 * scale * r - c2;
        *rho_prime = scale / r;
        second = -*rho_prime / (2.0 * s);
      }
      break;
    case Type::kCauchy:
      *rho = c2 * std::log1p(s / c2);
      *rho_prime = 1.0 / (1.0 + s / c2);
      second = -*rho_prime * *rho_prime / c2;
      break;
  }
  if (rho_second) *rho_second = second;
}

RobustLoss::Type RobustLoss::TypeFromName(const std::string& name) {
  if (name == "none") return Type::kNone;
  if (name == "huber") return Type::kHuber;
  if (name == "cauchy") return Type::kCauchy;
  throw std::invalid_argument("unknown robust loss '" + name + "' (expected none, huber or cauchy)");
}

double NormalEquations::PositionRms() const { return num_rows > 0 ? std::sqrt(position_squares / num_rows) : 0.0; }

NormalEquations AccumulateNormalEquations(const ErrorModelProblem& problem, const Eigen::VectorXd& x,
                                          const RowWeighting& weighting, Accumulate what, bool with_prior) {
  const int rows = problem.num_rows();
  if (!weighting.weights.empty()) {
    if (static_cast<int>(weighting.weights.size()) != rows) {
      throw std::invalid_argument("weights: expected one per row (" + std::to_string(rows) + "), got " +
                                  std::to_string(weighting.weights.size()));
    }
    for (double w : weighting.weights) {
      if (!(w >= 0.0) || !std::isfinite(w)) throw std::invalid_argument("weights must be finite and >= 0");
    }
  }
  if (weighting.loss.type != RobustLoss::Type::kNone && !(weighting.loss.scale > 0.0)) {
    throw std::invalid_argument("the robust loss scale must be positive");
  }
  const int p = problem.num_parameters();
  const bool gradient = what != Accumulate::kCost;
  const bool normal = what == Accumulate::kNormalEquations;
  NormalEquations out;
  out.num_rows = rows;
  if (gradient) out.Jtr.setZero(p);
  if (normal) out.JtJ.setZero(p, p);

  // Residual rows are packed as columns of Jt (p x block) for one rank-k update per block.
  constexpr int kBlockResiduals = 192;
  Eigen::MatrixXd Jt(p, gradient ? kBlockResiduals : 0);
  Eigen::VectorXd rb(gradient ? kBlockResiduals : 0);
  int filled = 0;
  const auto flush = [&]() {
    if (filled == 0) return;
    out.Jtr.noalias() += Jt.leftCols(filled) * rb.head(filled);
    if (normal) out.JtJ.selfadjointView<Eigen::Lower>().rankUpdate(Jt.leftCols(filled));
    filled = 0;
  };

  auto ws = problem.NewWorkspace();
  Vector6d r;
  Matrix6Xd J;
  for (int i = 0; i < rows; ++i) {
    const int k = problem.EvaluateRow(i, x, ws.get(), &r, gradient ? &J : nullptr);
    const double s = k == 6 ? r.squaredNorm() : r.head<3>().squaredNorm();
    double rho, rho_prime;
    weighting.loss.Evaluate(s, &rho, &rho_prime);
    const double w = weighting.weight(i);
    out.cost += w * rho;
    out.irls_squares += w * rho_prime * s;
    out.position_squares += r.head<3>().squaredNorm();
    if (w > 0.0) out.num_residuals += k;
    if (!gradient) continue;
    const double sqrt_w = std::sqrt(w * rho_prime);
    if (filled + k > kBlockResiduals) flush();
    Jt.middleCols(filled, k) = sqrt_w * J.topRows(k).transpose();
    for (int a = 0; a < k; ++a) rb[filled + a] = sqrt_w * r[a];
    filled += k;
  }
  if (gradient) flush();
  if (normal) out.JtJ.triangularView<Eigen::StrictlyUpper>() = out.JtJ.transpose();
  if (with_prior) AddPriorTerms(problem, x, &out);
  return out;
}

}  // namespace kincal
