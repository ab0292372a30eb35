#pragma once
// The calibration doctor's cheap fit: the robot file's geometry held, only what a set-up changes freely
// fitted (the measurement frame of every session, the position of every marker on the tool, and a small
// offset of every joint), by a few Levenberg-Marquardt steps with Huber weights. It is the yardstick of
// every hypothesis of doctor.h: a repair is a finding when it makes this fit clearly better.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "framework/dataset.h"
#include "robot/robot.h"

namespace kincal::doctor {

struct CheapFitOptions {
  bool free_markers = true;          // false: markers where the robot file puts them
  int iterations = 8;                // Levenberg-Marquardt steps
  double offset_prior_sd = 0.0873;   // rad (5 deg): joint offsets are small corrections, not 90 deg turns ...
  double max_offset = 0.1745;        // ... and never beyond 10 deg, rad
  double trim = 0.95;  // the score is the RMS of this fraction of rows (the best fitting): a fault in one
                       // joint of a sweep protocol shows in 1/n of the rows only, more than the trimmed 5 %
};

struct CheapFit {
  std::map<int, Eigen::Isometry3d> frames;         // T_meas_meas' correction per session
  std::map<std::string, Eigen::Vector3d> markers;  // tool frame, m
  Eigen::VectorXd offsets;                         // rad (m for prismatic joints)
  std::vector<Eigen::Vector3d> residuals;          // predicted - measured, m, one per row of the fitted data
  double score = 0.0;                              // trimmed RMS, m (CheapFitOptions::trim)
  double rms = 0.0;                                // plain RMS of every row, m
};

// Fits `data` with `robot` (its geometry held). Never throws for data it can read: a degenerate set-up
// gives a large score.
CheapFit FitCheap(const Robot& robot, const Dataset& data, const CheapFitOptions& options);
// Residuals (predicted - measured, m) of every row of `data` under a fit made on (a subset of) it.
std::vector<Eigen::Vector3d> Residuals(const Robot& robot, const Dataset& data, const CheapFit& fit);
// RMS of the `trim` fraction of smallest residual norms (trim 1: every row).
double TrimmedRms(const std::vector<Eigen::Vector3d>& residuals, double trim);
// The median of v (the upper one of an even count); 0 when empty.
double Median(std::vector<double> v);

}  // namespace kincal::doctor
