#pragma once
// DriveModel: each joint's motor, reduction and encoder (the seed's section 3, METHOD.md).
//   motor angle  = K_i * q_i                         (K_i: reduction ratio, motor turns per joint turn)
//   counts       = zero_i + C_i * K_i * q_i / (2 pi)  (C_i: encoder counts per motor revolution)
// A controller converts a commanded joint angle to counts with ITS ratio (usually the nominal one); the
// joint then turns to wherever those counts put it with the REAL ratio:
//   q_actual = q_commanded * K_controller / K_actual          (about the encoder zero)
// an error that grows with the angle and that no geometric parameter can absorb.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace kincal {

struct DriveModel {
  Eigen::VectorXd ratio;           // K_i
  Eigen::VectorXd counts_per_rev;  // C_i = encoder lines x levels per line
  Eigen::VectorXd encoder_zero;    // counts at q_i = 0; zeros if the file gives none

  int dof() const { return static_cast<int>(ratio.size()); }
  // Throws std::invalid_argument unless sizes agree and ratios and counts are finite and non-zero.
  void Validate(int expected_dof) const;

  // Exact (real-valued) counts at actual joint angles q.
  Eigen::VectorXd CountsFromAngles(const Eigen::VectorXd& q) const;
  // Actual joint angles at the given counts.
  Eigen::VectorXd AnglesFromCounts(const Eigen::VectorXd& counts) const;
  // Integer counts a controller using *this sends for commanded angles (rounded to the nearest count).
  std::vector<int64_t> CommandCounts(const Eigen::VectorXd& q_commanded) const;

  // q_actual = q_commanded * K_controller / K_actual.
  static Eigen::VectorXd ActualFromCommanded(const DriveModel& controller, const DriveModel& actual,
                                             const Eigen::VectorXd& q_commanded);
  // The inverse: what to command so that the joint reaches q_actual.
  static Eigen::VectorXd CommandedFromActual(const DriveModel& controller, const DriveModel& actual,
                                             const Eigen::VectorXd& q_actual);
};

}  // namespace kincal
