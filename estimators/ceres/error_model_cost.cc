#include "estimators/ceres/error_model_cost.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "estimators/error_model/prior_factor.h"

namespace kincal {

WorkspacePool::Lease WorkspacePool::Acquire() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!free_.empty()) {
      std::unique_ptr<Slot> slot = std::move(free_.back());
      free_.pop_back();
      return Lease(this, std::move(slot));
    }
  }
  auto slot = std::make_unique<Slot>();
  slot->workspace = problem_.NewWorkspace();
  slot->x = problem_.InitialX();
  return Lease(this, std::move(slot));
}

void WorkspacePool::Return(std::unique_ptr<Slot> slot) {
  std::lock_guard<std::mutex> lock(mutex_);
  free_.push_back(std::move(slot));
}

ErrorModelRowCost::ErrorModelRowCost(const ErrorModelProblem& problem, int row, std::vector<int> blocks,
                                     WorkspacePool* pool)
    : problem_(problem), row_(row), blocks_(std::move(blocks)), pool_(pool) {
  set_num_residuals(problem.RowResiduals(row));
  for (int b : blocks_) mutable_parameter_block_sizes()->push_back(problem.blocks()[b].size);
}

bool ErrorModelRowCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const WorkspacePool::Lease slot = pool_->Acquire();
  const std::vector<ParameterBlock>& all = problem_.blocks();
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const ParameterBlock& b = all[blocks_[k]];
    slot->x.segment(b.offset, b.size) = Eigen::Map<const Eigen::VectorXd>(parameters[k], b.size);
  }
  const int rows = problem_.EvaluateRow(row_, slot->x, slot->workspace.get(), &slot->residual,
                                        jacobians ? &slot->jacobian : nullptr);
  Eigen::Map<Eigen::VectorXd>(residuals, rows) = slot->residual.head(rows);
  if (!slot->residual.head(rows).allFinite()) return false;
  if (!jacobians) return true;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    if (!jacobians[k]) continue;
    const ParameterBlock& b = all[blocks_[k]];
    // Ceres' Jacobian blocks are row-major, rows x block size.
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[k], rows, b.size) =
        slot->jacobian.block(0, b.offset, rows, b.size);
  }
  return true;
}

namespace {

// The prior factors of one parameter block (prior_factor.h), so that Ceres' 1/2 sum r^2 matches the cost.
class PriorCost final : public ceres::CostFunction {
 public:
  PriorCost(int block_size, std::vector<int> index, std::vector<double> mean, std::vector<double> scale)
      : index_(std::move(index)), mean_(std::move(mean)), scale_(std::move(scale)) {
    set_num_residuals(static_cast<int>(index_.size()));
    mutable_parameter_block_sizes()->push_back(block_size);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int m = static_cast<int>(index_.size()), n = parameter_block_sizes()[0];
    for (int k = 0; k < m; ++k) residuals[k] = scale_[k] * (parameters[0][index_[k]] - mean_[k]);
    if (jacobians && jacobians[0]) {
      std::fill(jacobians[0], jacobians[0] + m * n, 0.0);
      for (int k = 0; k < m; ++k) jacobians[0][k * n + index_[k]] = scale_[k];
    }
    return true;
  }

 private:
  std::vector<int> index_;
  std::vector<double> mean_, scale_;
};

// The row weighting's robust loss (normal_equations.h) as Ceres reads it: rho on the squared norm, the
// same convention, so that the own LM and Ceres minimise the same cost.
class RobustLossFunction final : public ceres::LossFunction {
 public:
  explicit RobustLossFunction(const RobustLoss& loss) : loss_(loss) {}
  void Evaluate(double s, double rho[3]) const override { loss_.Evaluate(s, &rho[0], &rho[1], &rho[2]); }

 private:
  RobustLoss loss_;
};

}  // namespace

CeresErrorModel::CeresErrorModel(const ErrorModelProblem& problem, const RowWeighting& weighting,
                                 const Eigen::VectorXd& x0)
    : problem_(problem), x_(x0), pool_(problem) {
  if (x0.size() != problem.num_parameters()) throw std::invalid_argument("ceres: x0 has the wrong size");
  const int rows = problem.num_rows();
  if (!weighting.weights.empty() && static_cast<int>(weighting.weights.size()) != rows) {
    throw std::invalid_argument("ceres: " + std::to_string(weighting.weights.size()) + " weights for " +
                                std::to_string(rows) + " rows");
  }
  if (weighting.loss.type != RobustLoss::Type::kNone) loss_ = std::make_unique<RobustLossFunction>(weighting.loss);
  ceres::Problem::Options options;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres_problem_ = std::make_unique<ceres::Problem>(options);

  const std::vector<ParameterBlock>& blocks = problem.blocks();
  for (size_t b = 0; b < blocks.size(); ++b) {
    ceres_problem_->AddParameterBlock(block(static_cast<int>(b)), blocks[b].size);
    if (blocks[b].name == "base" || blocks[b].name.rfind("session:", 0) == 0) ++frame_blocks_;
  }
  if (!weighting.weights.empty()) scaled_.reserve(rows);
  std::vector<double*> pointers;
  for (int i = 0; i < rows; ++i) {
    std::vector<int> row_blocks = problem.RowBlocks(i);
    if (row_blocks.empty()) continue;  // nothing free acts on this row: a constant cost
    pointers.clear();
    for (int b : row_blocks) pointers.push_back(block(b));
    ceres::LossFunction* loss = loss_.get();
    if (!weighting.weights.empty()) {
      scaled_.push_back(
          std::make_unique<ceres::ScaledLoss>(loss_.get(), weighting.weights[i], ceres::DO_NOT_TAKE_OWNERSHIP));
      loss = scaled_.back().get();
    }
    ceres_problem_->AddResidualBlock(new ErrorModelRowCost(problem, i, std::move(row_blocks), &pool_), loss, pointers);
  }
  // The prior factors (prior_factor.h), grouped by parameter block.
  std::vector<std::vector<int>> index(blocks.size());
  std::vector<std::vector<double>> mean(blocks.size()), scale(blocks.size());
  for (const PriorFactor& f : PriorFactors(problem)) {
    size_t b = 0;
    while (b + 1 < blocks.size() && f.index >= blocks[b + 1].offset) ++b;
    index[b].push_back(f.index - blocks[b].offset);
    mean[b].push_back(f.mean);
    scale[b].push_back(f.scale);
  }
  for (size_t b = 0; b < blocks.size(); ++b) {
    if (index[b].empty()) continue;
    ceres_problem_->AddResidualBlock(
        new PriorCost(blocks[b].size, std::move(index[b]), std::move(mean[b]), std::move(scale[b])), nullptr,
        block(static_cast<int>(b)));
  }
}

}  // namespace kincal
