#pragma once
// The iteration shared by the iterative compensators (analytic_derivative, jacobian): Gauss-Newton on a
// pose residual r(q) of the identified robot, from the controller's nominal solution.
//
// Each step solves the linearization r(q + dq) ~ r(q) - A(q) dq in the least-squares sense. Away from
// singular configurations that is the plain Gauss-Newton step (quadratic convergence). Near them
// (rho = sigma_min / sigma_max of A below `singular_ratio`, detected from the singular values) the
// undamped step is the pseudo-inverse one without the directions whose singular values are at rounding
// level, and it falls back to damped least squares,
//     dq(mu) = (A^T A + mu I)^-1 A^T r,
// with the smallest damping mu >= 0 that keeps |dq| within `trust_radius`: Levenberg-Marquardt in its
// trust-region form (More 1978). The same limit applies to any step longer than the radius (a target far
// from the seed, or out of reach). The damping is therefore zero wherever the undamped step is short (a
// reachable target next to a singularity still converges quadratically) and grows only where sigma_min
// is small and the residual points along it. A step that does not reduce |r| is halved (a backtracking
// line search).
#include <string>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "compensators/compensator.h"
#include "framework/damped_least_squares.h"
#include "framework/registry.h"

namespace kincal {

struct GaussNewtonOptions {
  int max_iterations = 30;               // accepted steps
  double position_tolerance = 1e-12;     // m: converged when the position error is at most this ...
  double orientation_tolerance = 1e-12;  // rad: ... and the orientation error at most this
  // Near-singular when sigma_min / sigma_max of the (weighted) linearization falls below this ratio;
  // the step is then limited to trust_radius by damping. 0: never, every step is the plain
  // pseudo-inverse A^+ r (the seed's Delta_theta = A^+ B).
  double singular_ratio = 1e-3;
  // rad: the longest joint step (Euclidean norm); longer undamped steps are damped to it.
  double trust_radius = 0.3;
  // Halvings tried when a step does not reduce |r|; 0 disables the line search (every step is taken,
  // as in the seed).
  int max_step_halvings = 10;
  // Targets not reached from the seed are retried from the nominal arm's branches (compensators/compensator.h).
  BranchRestartOptions restarts;

  // The keys above and the restarts'.
  static const OptionTable<GaussNewtonOptions>& Table();
  bool IsValid(std::string* why) const;
};

// r(q), the quantity driven to zero, with its derivative A = -dr/dq (so that the step solves A dq = r).
class PoseResidual {
 public:
  virtual ~PoseResidual() = default;
  // Residual (weighted as the method defines it) and the unweighted errors the stop test uses:
  // position error in m, orientation error in rad (0 for position-only targets).
  virtual void Evaluate(const Eigen::VectorXd& q, Eigen::VectorXd* r, double* position_error,
                        double* orientation_error) const = 0;
  virtual void Linearize(const Eigen::VectorXd& q, Eigen::MatrixXd* A) const = 0;
};

// The step of one iteration; keeps its workspace between calls.
class DampedLeastSquares {
 public:
  struct Step {
    bool near_singular = false;  // rho < singular_ratio
    bool damped = false;         // the trust radius limited the step (mu > 0)
    double mu = 0.0;
    // sigma_min / sigma_max of A when it was computed, otherwise a proven lower bound of it.
    double sigma_ratio = 0.0;
    // |P r| / |r|, P the projection onto the range of A (singular values at rounding level left out):
    // the share of r that joint motion can reduce to first order; 0 at a least-squares point that
    // misses the target.
    double reducible_ratio = 0.0;
    // |dq| of the undamped step (pseudo-inverse without rounding-level singular values): how far the
    // linear model puts the solution.
    double undamped_norm = 0.0;
  };

  // Solves for dq (resized).
  //
  // The exact singular values cost an eigen-decomposition; it is computed only when a cheap bound
  // cannot exclude a near-singular A. With G = A^T A (or A A^T for a wide A) of size k,
  //     cond(A)^2 = lambda_max(G) / lambda_min(G) <= trace(G) * trace(G^-1) <= k^2 cond(A)^2,
  // and trace(G^-1) = |L^-1|_F^2 from the Cholesky factor G = L L^T the solve needs anyway. (The
  // eigen-decomposition path also catches a G too ill-conditioned for Cholesky.)
  Step Solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& r, const GaussNewtonOptions& options,
             Eigen::VectorXd* dq);

 private:
  // The 6 x 6 systems of 6-joint arms and 6-D targets at a size fixed at compile time, others dynamic.
  template <int Size>
  struct Workspace {
    DampedNormalEquations<Size> normal;
    Eigen::SelfAdjointEigenSolver<typename DampedNormalEquations<Size>::Matrix> eigen;
    typename DampedNormalEquations<Size>::Vector c, y;
  };
  template <int Size>
  Step SolveWith(Workspace<Size>* w, const Eigen::MatrixXd& A, const Eigen::VectorXd& r,
                 const GaussNewtonOptions& options, Eigen::VectorXd* dq);
  // Near-singular step from the eigen-decomposition of G: the smallest mu with |dq(mu)| <= radius.
  template <int Size>
  void TrustRegionStep(Workspace<Size>* w, const Eigen::MatrixXd& A, bool tall, double radius, Step* step,
                       Eigen::VectorXd* dq);

  Workspace<6> six_;
  Workspace<Eigen::Dynamic> any_;
  double residual_norm2_ = 0.0;
};

// Iterates from result->q_actual (the seed) and fills result->q_actual, the report's status, message,
// iterations and histories. Status when the tolerances are not met:
//   kUnreachable    joint motion can hardly reduce the residual (reducible_ratio < 0.1), or the linear
//                   model puts the solution more than a turn (2 pi rad) of joint motion away: at or
//                   heading for a least-squares point that misses the target;
//   kSingular       the last configuration is near singular (rho < singular_ratio);
//   kIterationLimit otherwise; kFailed if a step is not finite.
void RunGaussNewton(const PoseResidual& residual, const GaussNewtonOptions& options, CompensationResult* result);

}  // namespace kincal
