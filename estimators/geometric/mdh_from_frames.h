#pragma once
// Modified DH (Craig) parameters between two frames (METHOD.md 2, eqs. 4-7 restated), and back.
//   T_{i-1}^{i}(q_i) = Dx(a_i) * Rx(alpha_i) * Dz(d_i) * Rz(theta_i + q_i)
//   a_i     = (O_i - O_{i-1}) . X_{i-1}
//   d_i     = (O_i - O_{i-1}) . Z_i
//   alpha_i = atan2((Z_{i-1} x Z_i) . X_{i-1}, Z_{i-1} . Z_i)
//   theta_i = atan2((X_{i-1} x X_i) . Z_i, X_{i-1} . X_i) - q_i
// The paper's acos(.) * sgn(.) forms (eqs. 6, 7) are written with atan2: the same angle, without acos's
// loss of precision near 0 and pi. The formulas are exact when X_{i-1} is perpendicular to Z_i and
// O_i - O_{i-1} lies in the plane of X_{i-1} and Z_i, which the common-normal construction guarantees.
#include <Eigen/Geometry>

namespace kincal::geometric {

struct MdhRow {
  double alpha = 0.0, a = 0.0, theta = 0.0, d = 0.0;  // rad, m
  // Hayati's tilt about y after Rx(alpha) (models/hayati_model.h: Dx(a) Rx(alpha) Ry(beta) Dz(d) Rz(theta));
  // 0 in modified DH, whose rows are Hayati's with beta = 0.
  double beta = 0.0;
};

// Row i from frame i-1 and frame i (poses in one common frame) at joint angle q_i. theta in (-pi, pi].
MdhRow MdhRowFromFrames(const Eigen::Isometry3d& T_meas_prev, const Eigen::Isometry3d& T_meas_frame, double q);
// Row i in Hayati's convention, for frames whose z axes are nearly parallel: alpha and beta from the
// direction of Z_i in frame i-1 (Rx(alpha) Ry(beta) e_z), theta from the rest of the rotation, a and d
// from O_i - O_{i-1} = a X_{i-1} + d Z_i (exact when O_{i-1} + a X_{i-1} is on axis i, as
// FramesFromAxes places it when it keeps the tilt).
MdhRow HayatiRowFromFrames(const Eigen::Isometry3d& T_meas_prev, const Eigen::Isometry3d& T_meas_frame, double q);
// T_{i-1}^{i}(q) of a row (beta included).
Eigen::Isometry3d MdhTransform(const MdhRow& row, double q);

}  // namespace kincal::geometric
