#pragma once
// Frames from joint axes by common normals (METHOD.md 2, "Frames from axes"), at the calibration
// configuration, in the measurement frame.
//
// For i = 1..n-1, L_i is the common perpendicular of axes i and i+1; O_i is its foot on axis i, X_i its
// direction, Y_i = Z_i x X_i. Signs of X_i (the paper is silent or wrong, METHOD.md): the sign that
// gives alpha_{i+1} the nominal alpha's sign; for a nominal alpha near 0 or pi, the sign that gives
// a_{i+1} the nominal sign; failing both, the sign closest to the direction the nominal theta_i predicts
// (X_{i-1} turned by theta_i + q_i about Z_i). The last frame: O_n is the foot of L_{n-1} on axis n moved
// by the nominal d_n, X_n is X_{n-1} turned by the nominal theta_n + q_n, so that d_n and theta_n (which
// are redundant with the tool when only the marker's position is measured) keep their nominal values;
// for the seed, d_6 = theta_6 = 0 and this is METHOD.md's O_6 = foot of L_5, X_6 = X_5.
//
// Parallel or nearly parallel consecutive axes (angle below `parallel_threshold`): the common
// perpendicular is undefined or its foot runs far away (a tilt epsilon of axis i+1 toward axis i puts it
// at a / tan(epsilon)), and MDH cannot represent a tilt about y_i at all (that needs Hayati's beta).
// Convention, deterministic and bounded: the normal passes through the previous normal's foot on axis i
// moved by the nominal d_i (d_i keeps its nominal value, 0 for every common arm: Craig's "d = 0"
// choice); for i = 1, through the point of axis 1 nearest the fitted centre of axis 2. X_i points from
// there perpendicularly toward axis i+1 (made perpendicular to Z_i). Axis i+1 is then replaced by the
// line MDH can hold: through the normal's far end, its direction without the component along X_i; the
// dropped tilt is reported (it costs about tilt x distance along the axis at the marker).
// With keep_tilt (a Hayati robot, whose beta_{i+1} is that tilt), axis i+1 stays as fitted: the normal
// runs from the origin, perpendicular to Z_i, to where axis i+1 crosses that plane (HayatiRowFromFrames
// then reads alpha, a, beta, theta and d of row i+1 exactly).
#include <vector>

#include <Eigen/Geometry>

#include "estimators/geometric/mdh_from_frames.h"

namespace kincal::geometric {

struct AxisLine {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
};

struct JointPair {
  int joint = 0;              // the pair (joint, joint + 1), 1-based
  double angle = 0.0;         // angle between the two axes as lines, [0, pi/2], rad
  bool parallel = false;      // below the threshold: the convention above was used
  double dropped_tilt = 0.0;  // parallel pairs: tilt of axis joint+1 about y_joint that MDH cannot hold, rad
  double kept_tilt = 0.0;     // parallel pairs with keep_tilt: that tilt, held by the frames instead, rad
};

struct AxisFrames {
  std::vector<Eigen::Isometry3d> frames;  // T_meas_frame_i, i = 1..n (index i - 1)
  std::vector<JointPair> pairs;           // n - 1 entries
  std::vector<AxisLine> model_axes;       // the axes as the frames hold them (differ after a parallel pair)
};

// `nominal`: the start robot's MDH rows 1..n (signs and the conventions above); `q_cal`: the joint angles
// of the calibration configuration; `x1_hint`: a direction for X_1 when nothing else decides it (the
// nominal model's x_1 there). Never produces NaN for unit axis directions.
AxisFrames FramesFromAxes(const std::vector<AxisLine>& axes, const std::vector<MdhRow>& nominal,
                          const Eigen::VectorXd& q_cal, const Eigen::Vector3d& x1_hint, double parallel_threshold,
                          bool keep_tilt = false);

}  // namespace kincal::geometric
