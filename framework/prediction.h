#pragma once
// What a model predicts for a measurement row, and the error metrics every module scores with.
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "framework/robot.h"

namespace kincal {

// Actual joint angles of a row according to `model`. With encoder counts and drives, the angle the
// counts put the joint at with the model's ratios; otherwise the commanded angle scaled by
// K_controller / K_model (DriveModel::ActualFromCommanded), or unchanged when either has no drives.
Eigen::VectorXd ActualJointAngles(const Robot& controller, const Robot& model, const Measurement& m);

// T_meas_tool of `model` at actual joint angles q, in the frame of the row's session.
Eigen::Isometry3d PredictToolPose(const Robot& model, const Eigen::VectorXd& q_actual, int session = 0);

// Predicted marker position for a row (session base, marker offset, drives all applied).
Eigen::Vector3d PredictMarker(const Robot& controller, const Robot& model, const Measurement& m);

struct ErrorStats {
  int count = 0;
  double mean = 0.0;
  double rms = 0.0;
  double max = 0.0;
  double median = 0.0;
};
ErrorStats Summarize(std::vector<double> errors);

struct PredictionErrors {
  std::vector<double> position;     // m, one per row
  std::vector<double> orientation;  // rad, one per row with a measured orientation
  ErrorStats position_stats;
  ErrorStats orientation_stats;
};
// Errors of `model` in predicting every row of `data` (the controller's ratios give the commanded
// angles their meaning).
PredictionErrors EvaluatePredictions(const Robot& controller, const Robot& model, const Dataset& data);

}  // namespace kincal
