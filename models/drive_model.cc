#include "models/drive_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kincal {

void DriveModel::Validate(int expected_dof) const {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("drives: " + what); };
  if (ratio.size() != expected_dof) {
    fail("expected " + std::to_string(expected_dof) + " ratios, got " + std::to_string(ratio.size()));
  }
  if (counts_per_rev.size() != expected_dof) {
    fail("expected " + std::to_string(expected_dof) + " counts_per_rev, got " + std::to_string(counts_per_rev.size()));
  }
  if (encoder_zero.size() != expected_dof) {
    fail("expected " + std::to_string(expected_dof) + " encoder_zero values, got " +
         std::to_string(encoder_zero.size()));
  }
  for (int i = 0; i < expected_dof; ++i) {
    if (!std::isfinite(ratio[i]) || ratio[i] == 0.0)
      fail("ratio of joint " + std::to_string(i + 1) + " must be finite and non-zero");
    if (!std::isfinite(counts_per_rev[i]) || counts_per_rev[i] <= 0.0) {
      fail("counts_per_rev of joint " + std::to_string(i + 1) + " must be positive");
    }
    if (!std::isfinite(encoder_zero[i])) fail("encoder_zero of joint " + std::to_string(i + 1) + " must be finite");
  }
}

Eigen::VectorXd DriveModel::CountsFromAngles(const Eigen::VectorXd& q) const {
  return encoder_zero.array() + counts_per_rev.array() * ratio.array() * q.array() / (2.0 * M_PI);
}

Eigen::VectorXd DriveModel::AnglesFromCounts(const Eigen::VectorXd& counts) const {
  return (counts - encoder_zero).array() * (2.0 * M_PI) / (counts_per_rev.array() * ratio.array());
}

std::vector<int64_t> DriveModel::CommandCounts(const Eigen::VectorXd& q_commanded) const {
  // CountsFromAngles element by element, in the same order of operations, without a temporary.
  std::vector<int64_t> out(q_commanded.size());
  for (int i = 0; i < q_commanded.size(); ++i) {
    out[i] = std::llround(encoder_zero[i] + counts_per_rev[i] * ratio[i] * q_commanded[i] / (2.0 * M_PI));
  }
  return out;
}

Eigen::VectorXd DriveModel::ActualFromCommanded(const DriveModel& controller, const DriveModel& actual,
                                                const Eigen::VectorXd& q_commanded) {
  return q_commanded.array() * controller.ratio.array() / actual.ratio.array();
}

Eigen::VectorXd DriveModel::CommandedFromActual(const DriveModel& controller, const DriveModel& actual,
                                                const Eigen::VectorXd& q_actual) {
  return q_actual.array() * actual.ratio.array() / controller.ratio.array();
}

}  // namespace kincal
