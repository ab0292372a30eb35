#include "compensators/common/gauss_newton.h"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

namespace kincal {

const OptionTable<GaussNewtonOptions>& GaussNewtonOptions::Table() {
  using O = GaussNewtonOptions;
  static const OptionTable<O> table =
      OptionTable<O>("gauss-newton")
          .Add("max_iterations", &O::max_iterations, "accepted steps", AtLeast(0))
          .Add("position_tolerance", OptionUnit::kLength, &O::position_tolerance,
               "converged within this position error", Positive())
          .Add("orientation_tolerance", &O::orientation_tolerance, "rad: ... and this orientation error", Positive())
          .Add("singular_ratio", &O::singular_ratio, "sigma_min / sigma_max below which steps are damped",
               Between(0, 1, false, true))
          .Add("trust_radius", &O::trust_radius, "rad: the longest joint step", Positive())
          .Add("max_step_halvings", &O::max_step_halvings, "line-search halvings; 0: every step taken", Within(0, 60))
          .Include(BranchRestartOptions::Table(), &O::restarts);
  return table;
}

bool GaussNewtonOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

namespace {

// |A x| without a temporary.
double ProductNorm(const Eigen::MatrixXd& A, const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (int i = 0; i < A.rows(); ++i) {
    const double v = A.row(i).dot(x);
    sum += v * v;
  }
  return std::sqrt(sum);
}

}  // namespace

DampedLeastSquares::Step DampedLeastSquares::Solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& r,
                                                   const GaussNewtonOptions& options, Eigen::VectorXd* dq) {
  const Eigen::Index k = std::min(A.rows(), A.cols());
  return k == 6 ? SolveWith(&six_, A, r, options, dq) : SolveWith(&any_, A, r, options, dq);
}

template <int Size>
DampedLeastSquares::Step DampedLeastSquares::SolveWith(Workspace<Size>* w, const Eigen::MatrixXd& A,
                                                       const Eigen::VectorXd& r, const GaussNewtonOptions& options,
                                                       Eigen::VectorXd* dq) {
  Step step;
  const int m = static_cast<int>(A.rows()), n = static_cast<int>(A.cols());
  const bool tall = m >= n;
  residual_norm2_ = r.squaredNorm();
  const double r_norm = std::sqrt(residual_norm2_);
  // P r: the undamped step fits the part of r in the range of A.
  const auto reducible = [&](const Eigen::VectorXd& undamped) {
    return r_norm > 0 ? ProductNorm(A, undamped) / r_norm : 0.0;
  };
  if (options.singular_ratio <= 0.0) {
    // The seed's Delta_theta = A^+ B: the minimum-norm least-squares solution, rank deficient or not.
    *dq = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(r);
    step.undamped_norm = dq->norm();
    step.reducible_ratio = reducible(*dq);
    return step;
  }
  DampedNormalEquations<Size>& normal = w->normal;
  if (tall) {
    normal.Assemble(A, r);
  } else {
    normal.AssembleWide(A, r);
  }
  const bool factored = normal.Factor();
  if (factored) step.sigma_ratio = 1.0 / std::sqrt(normal.H().trace() * normal.InverseTrace());
  if (step.sigma_ratio < options.singular_ratio) {
    w->eigen.compute(normal.H(), Eigen::ComputeEigenvectors);
    const double lambda_max = std::max(w->eigen.eigenvalues().maxCoeff(), 0.0);
    const double lambda_min = std::max(w->eigen.eigenvalues().minCoeff(), 0.0);
    step.sigma_ratio = lambda_max > 0 ? std::sqrt(lambda_min / lambda_max) : 0.0;
    if (step.sigma_ratio < options.singular_ratio || !factored) {
      step.near_singular = step.sigma_ratio < options.singular_ratio;
      TrustRegionStep(w, A, tall, options.trust_radius, &step, dq);
      return step;
    }
  }
  w->y = normal.Step();
  if (tall) {
    *dq = w->y;
  } else {
    dq->resize(n);
    for (int j = 0; j < n; ++j) (*dq)[j] = A.col(j).dot(w->y);
  }
  step.undamped_norm = dq->norm();
  step.reducible_ratio = reducible(*dq);
  if (step.undamped_norm > options.trust_radius) {
    // Far from the target (or a target out of reach): the linear model is not trusted that far.
    w->eigen.compute(normal.H(), Eigen::ComputeEigenvectors);
    TrustRegionStep(w, A, tall, options.trust_radius, &step, dq);
  }
  return step;
}

template <int Size>
void DampedLeastSquares::TrustRegionStep(Workspace<Size>* w, const Eigen::MatrixXd& A, bool tall, double radius,
                                         Step* step, Eigen::VectorXd* dq) {
  const auto& lambda = w->eigen.eigenvalues();
  const auto& V = w->eigen.eigenvectors();
  const auto& g = w->normal.g();
  auto& c = w->c;
  const int k = static_cast<int>(lambda.size());
  c.noalias() = V.transpose() * g;
  // Eigenvalues at rounding level carry no information: dropped from the undamped step (pseudo-inverse).
  const double floor = std::max(lambda.maxCoeff(), 0.0) * k * 1e-15;
  // s(mu) = |dq(mu)|^2 = sum_i w_i c_i^2 / (lambda_i + mu)^2, w_i = 1 (tall: dq = V y) or lambda_i (wide:
  // dq = A^T V y); also returns s'(mu) in *slope.
  const auto step_norm2 = [&](double mu, double* slope) {
    double sum = 0.0, derivative = 0.0;
    for (int i = 0; i < k; ++i) {
      const double l = std::max(lambda[i], 0.0);
      if (mu == 0.0 && l <= floor) continue;
      const double y = c[i] / (l + mu);
      const double weight = tall ? 1.0 : l;
      sum += weight * y * y;
      derivative -= 2 * weight * y * y / (l + mu);
    }
    if (slope) *slope = derivative;
    return sum;
  };
  const auto step_norm = [&](double mu) { return std::sqrt(step_norm2(mu, nullptr)); };
  double mu = 0.0;
  step->undamped_norm = step_norm(0.0);
  // |P r|^2 = sum over informative eigenvalues of c_i^2 / lambda_i (tall: c = V^T A^T r) or c_i^2 (wide).
  double fit2 = 0.0;
  for (int i = 0; i < k; ++i) {
    if (lambda[i] > floor) fit2 += tall ? c[i] * c[i] / lambda[i] : c[i] * c[i];
  }
  const double r_norm = tall ? std::sqrt(std::max(residual_norm2_, 0.0)) : g.norm();
  step->reducible_ratio = r_norm > 0 ? std::sqrt(fit2) / r_norm : 0.0;
  if (step->undamped_norm > radius) {
    // |dq(mu)| = radius: Newton's method on 1 / |dq(mu)| - 1 / radius, which is concave and nearly
    // linear in mu (More & Sorensen 1983), so that iterates started left of the root (|dq| > radius)
    // increase monotonically towards it.
    mu = std::max(lambda.maxCoeff(), 1e-300) * 1e-15;
    for (int i = 0; i < 100; ++i) {
      double slope = 0.0;
      const double norm = std::sqrt(step_norm2(mu, &slope));
      if (norm <= radius * (1 + 1e-12)) break;
      mu += 2 * norm * norm * (norm / radius - 1) / std::max(-slope, 1e-300);
    }
    step->damped = true;
  }
  step->mu = mu;
  w->y.resize(k);
  for (int i = 0; i < k; ++i) {
    const double l = std::max(lambda[i], 0.0);
    w->y[i] = (mu == 0.0 && l <= floor) ? 0.0 : c[i] / (l + mu);
  }
  const typename DampedNormalEquations<Size>::Vector v = V * w->y;
  if (tall) {
    *dq = v;
  } else {
    dq->resize(A.cols());
    for (int j = 0; j < A.cols(); ++j) (*dq)[j] = A.col(j).dot(v);
  }
}

void RunGaussNewton(const PoseResidual& residual, const GaussNewtonOptions& o, CompensationResult* result) {
  CompensationReport& report = result->report;
  Eigen::VectorXd q = result->q_actual;
  Eigen::VectorXd r, r_trial, dq, q_trial;
  Eigen::MatrixXd A;
  DampedLeastSquares solver;
  DampedLeastSquares::Step last;
  double pe = 0.0, oe = 0.0;
  residual.Evaluate(q, &r, &pe, &oe);
  double cost = r.squaredNorm();
  report.position_history.reserve(o.max_iterations + 1);
  report.orientation_history.reserve(o.max_iterations + 1);
  report.position_history.push_back(pe);
  report.orientation_history.push_back(oe);
  report.iterations = 0;
  while (true) {
    if (pe <= o.position_tolerance && oe <= o.orientation_tolerance) {
      report.status = CompensationStatus::kConverged;
      break;
    }
    residual.Linearize(q, &A);
    last = solver.Solve(A, r, o, &dq);
    if (report.iterations >= o.max_iterations) {
      if (last.reducible_ratio < 0.1 || last.undamped_norm > 2 * M_PI) {
        report.status = CompensationStatus::kUnreachable;
        report.message = "joint motion cannot reduce the error: the target is out of reach";
      } else if (last.near_singular) {
        report.status = CompensationStatus::kSingular;
        report.message = "stopped near a singular configuration";
      } else {
        report.status = CompensationStatus::kIterationLimit;
      }
      break;
    }
    if (!dq.allFinite()) {
      report.status = CompensationStatus::kFailed;
      report.message = "non-finite step";
      break;
    }
    double t = 1.0, pe_trial = 0.0, oe_trial = 0.0, cost_trial = 0.0;
    bool accepted = false;
    for (int halving = 0;; ++halving) {
      q_trial = q + t * dq;
      residual.Evaluate(q_trial, &r_trial, &pe_trial, &oe_trial);
      cost_trial = r_trial.squaredNorm();
      if (o.max_step_halvings == 0 || cost_trial < cost) {
        accepted = true;
        break;
      }
      if (halving == o.max_step_halvings) break;
      t *= 0.5;
    }
    if (!accepted) {
      // No step reduces |r|: a least-squares point, or the floating-point floor of a reachable target.
      if (last.reducible_ratio < 0.1 || last.undamped_norm > 2 * M_PI) {
        report.status = CompensationStatus::kUnreachable;
        report.message = "the error has a local minimum here: the target is out of reach";
      } else {
        report.status = last.near_singular ? CompensationStatus::kSingular : CompensationStatus::kIterationLimit;
        report.message = "no step reduces the error further: the floating-point floor";
      }
      break;
    }
    q.swap(q_trial);
    r.swap(r_trial);
    cost = cost_trial;
    pe = pe_trial;
    oe = oe_trial;
    ++report.iterations;
    report.position_history.push_back(pe);
    report.orientation_history.push_back(oe);
  }
  result->q_actual = q;
}

}  // namespace kincal
