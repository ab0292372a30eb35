#pragma once
// The error model (estimators/error_model) as a ceres::Problem: the vector x of the ErrorModelProblem
// split into its parameter blocks (ErrorModelProblem::blocks(): geometry, ratios, each marker, the base,
// each session's base) and one residual block per dataset row over the blocks that row touches
// (RowBlocks), with analytic derivatives (ErrorModelRowCost calls ErrorModelProblem::EvaluateRow).
// Rows of different sessions touch different base blocks, which makes the Jacobian block sparse.
//
// Weighting as in normal_equations.h: row i costs w_i rho(|r_i|^2), rho on the row's squared norm
// (Ceres' own convention; the loss function calls RobustLoss::Evaluate itself, so the robust loss is
// defined once); the weight enters through ScaledLoss. Ceres minimises half of sum w rho: the same
// minimiser. Priors: one residual block per parameter block from PriorFactors (prior_factor.h).
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/normal_equations.h"

namespace kincal {

// Scratch for ErrorModelRowCost. Ceres may evaluate residual blocks from several threads and does not
// say which thread runs which block, so each evaluation leases a workspace for its duration.
class WorkspacePool {
 public:
  struct Slot {
    std::unique_ptr<ErrorModelProblem::Workspace> workspace;
    // The full x EvaluateRow needs. A row overwrites the blocks it touches; the others keep the values
    // of an earlier row, which this row's residual does not depend on (a session's rows see the model
    // base only through B_k B_0^-1 B_0, other markers not at all).
    Eigen::VectorXd x;
    Vector6d residual;
    Matrix6Xd jacobian;
  };
  class Lease {
   public:
    Lease(WorkspacePool* pool, std::unique_ptr<Slot> slot) : pool_(pool), slot_(std::move(slot)) {}
    Lease(Lease&&) = default;
    ~Lease() {
      if (slot_) pool_->Return(std::move(slot_));
    }
    Slot* operator->() const { return slot_.get(); }

   private:
    WorkspacePool* pool_;
    std::unique_ptr<Slot> slot_;
  };

  explicit WorkspacePool(const ErrorModelProblem& problem) : problem_(problem) {}
  Lease Acquire();

 private:
  void Return(std::unique_ptr<Slot> slot);
  const ErrorModelProblem& problem_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Slot>> free_;
};

class ErrorModelRowCost final : public ceres::CostFunction {
 public:
  // `blocks`: indices into problem.blocks(), in the order of Ceres' parameter blocks for this row.
  ErrorModelRowCost(const ErrorModelProblem& problem, int row, std::vector<int> blocks, WorkspacePool* pool);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  const ErrorModelProblem& problem_;
  int row_;
  std::vector<int> blocks_;
  WorkspacePool* pool_;
};

// The ceres::Problem of an ErrorModelProblem, with the storage it points into. `problem` must outlive it.
class CeresErrorModel {
 public:
  // x starts at x0 (problem.num_parameters() entries). Throws std::invalid_argument if the weighting
  // has the wrong number of weights.
  CeresErrorModel(const ErrorModelProblem& problem, const RowWeighting& weighting, const Eigen::VectorXd& x0);
  CeresErrorModel(const CeresErrorModel&) = delete;
  CeresErrorModel& operator=(const CeresErrorModel&) = delete;

  ceres::Problem& problem() { return *ceres_problem_; }
  const Eigen::VectorXd& x() const { return x_; }
  // Ceres' parameter block of problem.blocks()[b] (a pointer into x()).
  double* block(int b) { return x_.data() + problem_.blocks()[b].offset; }
  // Whether J^T J has zero blocks because different rows touch different base blocks (sessions).
  bool sessions_make_it_sparse() const { return frame_blocks_ > 1; }

 private:
  const ErrorModelProblem& problem_;
  Eigen::VectorXd x_;
  WorkspacePool pool_;
  std::unique_ptr<ceres::LossFunction> loss_;                 // shared by every row, may be null
  std::vector<std::unique_ptr<ceres::LossFunction>> scaled_;  // per-row weights
  std::unique_ptr<ceres::Problem> ceres_problem_;
  int frame_blocks_ = 0;
};

}  // namespace kincal
