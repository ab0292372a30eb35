#pragma once
// From the fitted arcs to a complete MDH (or Hayati) robot (METHOD.md 2): axes at the calibration configuration,
// frames by common normals, the MDH table (eqs. 4-7), base and tool.
//
// Axes at one configuration. Frames are built from axes that must all be where they were at the
// calibration configuration. With the seed's order (n..1) each axis is measured there already. When a
// proximal joint i was away from it during joint j's sweep (another order), axis j is turned back about
// the already-known axes i < j (proximal first), each by the angle joint i had turned, measured on joint
// i's own arc: angle_slope_i x (drive displacement); for the product of exponentials at the calibration
// configuration, exp(S_1 t_1) ... exp(S_{j-1} t_{j-1}) moves every link beyond j-1, so its inverse brings
// axis j back.
//
// Joint angles. No commanded step size enters: the actual angle of joint i at the calibration
// configuration is measured on its arc too, q_i,cal = angle_slope_i x (drive variable there) =
// (K_start / K_actual) x (start robot's angle), the angle from the encoder zero with the ratio the arc
// shows. So theta_i = angle(X_{i-1}, X_i) - q_i,cal (METHOD.md eq. 7) is the offset from the encoder zero
// whatever the ratios, and ratio_regression need not touch it. (The geometric stage's robot keeps the
// start ratios, so it is exact at zero counts and errs by (1 - K_start / K_actual) q elsewhere, until
// ratio_regression follows. For the seed's protocol q_cal is zero counts and the question does not arise.)
// A robot without drives keeps its readings as its angles, and then the readings are used here too
// (angles_from_readings; GeometricEstimator::Options::joint_angles explains why).
//
// Redundant parameters, held at the start robot's values: row 1 (alpha_1, a_1, theta_1, d_1), which the
// base absorbs, and d_n, theta_n, which the tool absorbs (the marker's position is all that is
// measured); and the tool's orientation, which a position cannot show. Frame 0 is then frame 1 at the
// calibration configuration moved back through row 1: T_meas_0 = T_meas_1(q_cal) T_0^1(q_1,cal)^-1;
// for the seed's zero row 1 and q_1,cal = 0 it is METHOD.md's "frame 0 is frame 1 at the calibration
// configuration".
#include <string>
#include <vector>

#include "estimators/geometric/arc_fit.h"
#include "estimators/geometric/common_normals.h"
#include "estimators/geometric/sweeps.h"
#include "robot/robot.h"

namespace kincal::geometric {

struct GeometricProblem {
  Robot start;            // the start robot, modified DH (models/conversion.h) or Hayati
  Eigen::VectorXd x_cal;  // joint angles of the calibration configuration (start drives)
  std::vector<std::vector<std::pair<int, double>>> moved;   // per joint: Sweep::moved
  std::vector<MdhRow> nominal;                              // the start robot's MDH rows
  Eigen::Vector3d x1_hint = Eigen::Vector3d::UnitX();       // the start model's x_1 at the calibration configuration
  Eigen::Vector3d p_tool_marker = Eigen::Vector3d::Zero();  // the (first) marker in the tool frame (start robot)
  int markers = 1;                                          // markers fitted together (SweepSet::markers)
  // The drive variables are the joint angles (GeometricEstimator::Options::joint_angles "readings"):
  // q_cal and the turns back use them instead of angle_slope x drive variable.
  bool angles_from_readings = false;
  double parallel_threshold = 1.0 * M_PI / 180.0;
  // A Hayati start: the rows after parallel pairs keep the tilt of their axis in beta (common_normals.h).
  bool keep_tilt = false;

  // Everything above from the sweeps and the start robot (which must be MDH or Hayati).
  static GeometricProblem Make(const Robot& mdh_start, const SweepSet& sweeps, double parallel_threshold);
};

struct GeometricSolution {
  std::vector<AxisLine> axes;  // fitted axes at the calibration configuration, i = 1..n
  AxisFrames frames;           // T_meas_frame_i at the calibration configuration
  std::vector<MdhRow> rows;    // identified table
  Eigen::Isometry3d T_meas_base = Eigen::Isometry3d::Identity();
  Eigen::Vector3d p_meas_marker = Eigen::Vector3d::Zero();  // (first) marker at the calibration configuration
  std::vector<Eigen::Vector3d> p_meas_markers;              // every marker there (SweepSet::markers order)
  // Several markers: each marker in the tool frame (the tool keeps the start robot's transform, which the
  // markers make redundant). One marker: empty; the tool's translation carries it, as below.
  Eigen::VectorXd q_cal;       // actual joint angles there, measured on the arcs
  Eigen::VectorXd parameters;  // the MDH model's parameter vector (ParameterNames() order)
  std::vector<Eigen::Vector3d> p_tool_markers;
};

// `fits`: one per joint, index joint - 1 (every joint swept).
GeometricSolution SolveGeometry(const GeometricProblem& problem, const std::vector<ArcFit>& fits);

}  // namespace kincal::geometric
