#pragma once
// The ABB IRB 120 position set of ../shared/data/irb120_wu2015 (data README; L. Wu, X. Yang, K. Chen,
// H. Ren, "A minimal POE-based model for robotic kinematic calibration with only position
// measurements", IEEE T-ASE 12(2), 2015): 36 calibration configurations with three points on the tool
// measured in each, and two held-out test sets. Used by tests only; never copied into the project.
//
// Protocol (the published Experiment.m): calibrate on the 108 points of the 36 configurations (points 1,
// 2 and 3 of every configuration, markers "p1", "p2", "p3"), then predict TestPosition (10
// configurations) and TestPosition2 (30 configurations). The test points are not calibration points: the
// published code places each in the tool frame from one measurement of it at the zero configuration (not
// in the data files). Both sit by calibration point 1 (test point 1 within 0.15 mm of it, test point 2
// 1.2 mm away), so the test rows name marker "p1"; a test that needs the exact point fits its position
// on the tool from the test rows.
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "robot/prediction.h"

namespace kincal::testing {

// Numbers of a comma-separated file with one header line (which may carry a '#' comment); each row must
// have `columns` numbers. Empty when the file is absent.
inline std::vector<std::vector<double>> ReadCsvTable(const std::string& path, size_t columns) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  if (!std::getline(in, line)) return rows;  // header
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    if (row.size() != columns) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected " + std::to_string(columns) +
                               " numbers");
    }
    rows.push_back(row);
  }
  return rows;
}

struct Irb120Wu2015 {
  Dataset calibration;  // 108 rows: configuration by configuration, points p1, p2, p3
  Dataset test1;        // 10 rows, marker p1 (TestJointAngles, TestPosition)
  Dataset test2;        // 30 rows, marker p1 (TestJointAngles2, TestPosition2)
};

namespace detail {

inline Dataset Wu2015Rows(const std::vector<std::vector<double>>& joints,
                          const std::vector<std::vector<double>>& points, size_t points_per_configuration,
                          const std::vector<std::string>& markers, const std::string& source) {
  if (points.size() != joints.size() * points_per_configuration) {
    throw std::runtime_error(source + ": " + std::to_string(points.size()) + " points for " +
                             std::to_string(joints.size()) + " configurations");
  }
  Dataset data;
  data.dof = 6;
  data.source = source;
  for (size_t i = 0; i < points.size(); ++i) {
    const std::vector<double>& q = joints[i / points_per_configuration];
    Measurement m;
    m.q.resize(6);
    for (int j = 0; j < 6; ++j) m.q[j] = q[j] * M_PI / 180.0;
    m.p = Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) * 1e-3;
    m.marker = markers[i % points_per_configuration];
    m.line = static_cast<int>(i + 2);
    data.rows.push_back(m);
  }
  return data;
}

}  // namespace detail

// False when the data folder is absent.
inline bool LoadIrb120Wu2015(const std::string& folder, Irb120Wu2015* out) {
  const auto cali_q = ReadCsvTable(folder + "/CaliJointAngles.csv", 6);
  if (cali_q.empty()) return false;
  out->calibration = detail::Wu2015Rows(cali_q, ReadCsvTable(folder + "/CaliPosition.csv", 3), 3, {"p1", "p2", "p3"},
                                        folder + "/CaliPosition.csv");
  out->test1 =
      detail::Wu2015Rows(ReadCsvTable(folder + "/TestJointAngles.csv", 6),
                         ReadCsvTable(folder + "/TestPosition.csv", 3), 1, {"p1"}, folder + "/TestPosition.csv");
  out->test2 =
      detail::Wu2015Rows(ReadCsvTable(folder + "/TestJointAngles2.csv", 6),
                         ReadCsvTable(folder + "/TestPosition2.csv", 3), 1, {"p1"}, folder + "/TestPosition2.csv");
  return true;
}

// The held-out RMS of `data` (one test point) with the point's tool-frame position fitted on those rows
// in closed form, the identified robot held: the published protocol measures each test point on its own,
// so its position on the tool is not one of the calibration's three points.
inline double RmsWithTestPointFitted(const Robot& controller, const Robot& identified, const Dataset& data) {
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < data.rows.size(); ++i) {
    poses.push_back(PredictToolPose(identified, ActualJointAngles(controller, identified, data, i, previous)));
    sum += poses.back().linear().transpose() * (data.rows[i].p - poses.back().translation());
  }
  const Eigen::Vector3d point = sum / static_cast<double>(data.rows.size());  // R^T R = I: the mean
  double sum2 = 0.0;
  for (size_t i = 0; i < data.rows.size(); ++i) sum2 += (poses[i] * point - data.rows[i].p).squaredNorm();
  return std::sqrt(sum2 / data.rows.size());
}

}  // namespace kincal::testing
