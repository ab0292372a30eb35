#pragma once
// The sweeps of a dataset (METHOD.md 2): rows with `sweep` = j (1-based) are the stops of joint j's
// sweep. Everything the geometric and ratio estimators need from the rows, checked once.
//
// Drive variable. Each stop's joint angles are taken as the start robot understands them: from the
// encoder counts and the start robot's drives when the rows carry counts, else the commanded angle scaled
// by K_controller / K_start (prediction.h, ActualJointAngles). They differ from the true angles by the
// unknown factor K_start / K_true, so the geometric construction uses them only for order and sign and
// measures every angle it needs on the fitted arcs; the ratio regression measures that factor.
//
// Calibration configuration. The commanded configuration of the first sweep row (in row order): for the
// seed's protocol (joints swept n..1 from the start) the first stop of joint n's sweep. A joint swept
// earlier stays where its sweep ended; with the order n..1 that moves only joints distal to the ones still
// to be swept, so every axis is measured at the calibration configuration. Other orders move proximal
// joints before a sweep; `moved` lists them and the solver turns the axis back (geometric_solver.h).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "robot/robot.h"

namespace kincal::geometric {

struct Sweep {
  int joint = 0;                        // 1-based
  std::vector<Eigen::Vector3d> points;  // measured marker positions, m (the first marker's)
  // Every marker's positions at the same stops, in SweepSet::markers order (marker_points[0] == points).
  std::vector<std::vector<Eigen::Vector3d>> marker_points;
  std::vector<double> x;  // the swept joint's drive variable at each stop, rad
  // Joints proximal to this one that were away from the calibration configuration during the sweep:
  // (0-based joint, drive-variable displacement from the calibration configuration).
  std::vector<std::pair<int, double>> moved;
  int first_line = 0, last_line = 0;  // source lines (0 when the rows were made in memory)
  int first_row = 0, last_row = 0;    // 0-based row indices
};

struct SweepSet {
  int dof = 0;
  std::vector<Sweep> sweeps;         // indexed by joint - 1; joint == 0 where a joint was never swept
  std::vector<int> order;            // 1-based joints in the order their sweeps start
  Eigen::VectorXd q_cal;             // commanded calibration configuration
  Eigen::VectorXd x_cal;             // its drive variables (the start robot's joint angles there)
  int cal_row = 0;                   // row index of the calibration configuration
  std::string marker;                // marker id used ("" = the tool origin); the first of `markers`
  std::vector<std::string> markers;  // every marker used (several: see ExtractSweeps)
  int session = 0;
  int free_rows = 0;  // rows with sweep 0 (not used)

  bool Swept(int joint) const { return sweeps[joint - 1].joint == joint; }
  // "sweep of joint 3 (data.csv lines 42-61)" for messages.
  std::string Where(int joint, const std::string& source) const;
};

// Held joints are judged on the readings through the start robot's coupling (a FANUC J2 sweep moves
// the J3 reading with it and holds the physical joint 3).
//
// Several markers: with `marker` empty and `several_markers`, every marker the sweep rows record is used
// (in order of first appearance); a sweep's k-th row of each marker is its k-th stop, so every marker
// must be measured at every stop, with the same joint values. Otherwise one marker is used: `marker`, or
// the only one.
//
// Throws std::invalid_argument naming the rows for: no sweep rows, a sweep in which another joint moves,
// several markers without `marker` chosen (unless several_markers), an unknown marker, several sessions,
// a stop some marker misses. `who` prefixes messages. Joints never swept are left out (Swept() false);
// the caller decides whether that is an error.
SweepSet ExtractSweeps(const Robot& controller, const Robot& start, const Dataset& data, const std::string& marker,
                       const std::string& who, bool several_markers = false);

}  // namespace kincal::geometric
