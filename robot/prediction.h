#pragma once
// What a model predicts for a measurement row, and the error metrics every module scores with.
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "robot/joint_readings.h"
#include "robot/robot.h"

namespace kincal {

// Actual joint angles of a row: robot/joint_readings.h (coupling, drives, joint errors).

// T_meas_tool of `model` at actual joint angles q, in the frame of the row's session.
Eigen::Isometry3d PredictToolPose(const Robot& model, const Eigen::VectorXd& q_actual, int session = 0);

// Predicted marker position of row `row` (coupling, drives, joint errors with the row's previous pose,
// session base and marker offset all applied); `previous` = data.PreviousPoses().
Eigen::Vector3d PredictMarker(const Robot& controller, const Robot& model, const Dataset& data, size_t row,
                              const std::vector<Dataset::Previous>& previous);
// Predicted marker positions of every row, in order.
std::vector<Eigen::Vector3d> PredictMarkers(const Robot& controller, const Robot& model, const Dataset& data);

// The residual of a row in its own kind, from the predicted marker position in the frame of the row's
// session and the robot's fixtures (robot/fixtures.h, in the frame of session 0):
//   point: predicted - measured on the measured axes (1 to 3 values, m);
//   distance: |predicted - pivot| - distance (1, m); plane: n . predicted - offset (1, m);
//   fixed point: predicted - point (3, m).
// Throws std::invalid_argument ("source:line: ...") when the robot does not give the row's fixture.
Eigen::VectorXd RowResidual(const Robot& model, const Dataset& data, size_t row, const Eigen::Vector3d& predicted);

struct ErrorStats {
  int count = 0;
  double mean = 0.0;
  double rms = 0.0;
  double max = 0.0;
  double median = 0.0;
};
ErrorStats Summarize(std::vector<double> errors);

struct PredictionErrors {
  std::vector<double> position;     // m, one per row: the norm of its residual in its own kind (RowResidual)
  std::vector<double> orientation;  // rad, one per row with a measured orientation
  ErrorStats position_stats;
  ErrorStats orientation_stats;
};
// Errors of `model` in predicting every row of `data` (the controller's ratios give the commanded
// angles their meaning).
PredictionErrors EvaluatePredictions(const Robot& controller, const Robot& model, const Dataset& data);

}  // namespace kincal
