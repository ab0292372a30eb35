#pragma once
// The ABB IRB 120 laser-tracker set of ../shared/data/irb120_faro (data README): 982 processed poses,
// joints read back from the controller (deg) and reflector positions (mm) in the tracker frame. Used by
// tests and benchmarks only; never copied into the project.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "framework/robot_file.h"

namespace kincal::testing {

// Nominal geometry (modified DH, Craig), the data README's table. No drives: the controller reports
// joint angles. The reflector's offset from the flange is unknown: the tool starts at the flange.
inline Robot Irb120FaroNominal() {
  return ParseRobotYaml(R"(
name: irb120_faro_nominal
convention: mdh
units: {length: mm, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 290}
  - {alpha: -90, a: 0, theta: -90, d: 0}
  - {alpha: 0, a: 270, theta: 0, d: 0}
  - {alpha: -90, a: 70, theta: 0, d: 302}
  - {alpha: 90, a: 0, theta: 0, d: 0}
  - {alpha: -90, a: 0, theta: 180, d: 72}
limits: [[-165, 165], [-110, 110], [-110, 70], [-160, 160], [-120, 120], [-400, 400]]
)",
                        "irb120_faro_nominal");
}

inline std::vector<std::vector<double>> ReadWhitespaceTable(const std::string& path, size_t columns) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::vector<double> row;
    double v;
    while (ss >> v) row.push_back(v);
    if (row.empty()) continue;
    if (row.size() != columns) throw std::runtime_error(path + ": expected " + std::to_string(columns) + " columns");
    rows.push_back(row);
  }
  return rows;
}

// Rows of the processed files with reflector `smr` (1..3) as the measured point; false when the data
// folder is absent. Row i of the joints file matches row i of the reflector file.
inline bool LoadIrb120Faro(const std::string& folder, int smr, Dataset* data) {
  const std::string joints_path = folder + "/processed_joints.txt";
  if (!std::ifstream(joints_path).good()) return false;
  const auto joints = ReadWhitespaceTable(joints_path, 6);
  const auto points = ReadWhitespaceTable(folder + "/processed_SMR_" + std::to_string(smr) + ".txt", 3);
  if (joints.size() != points.size()) throw std::runtime_error(folder + ": joints and reflector rows differ");
  data->dof = 6;
  data->source = folder;
  data->rows.clear();
  for (size_t i = 0; i < joints.size(); ++i) {
    Measurement m;
    m.q.resize(6);
    for (int j = 0; j < 6; ++j) m.q[j] = joints[i][j] * M_PI / 180.0;
    m.p = Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) * 1e-3;
    m.line = static_cast<int>(i + 1);
    data->rows.push_back(m);
  }
  return true;
}

// Even rows (0, 2, ...) and odd rows, the data README's split. Each row keeps the pose measured before
// it in the whole sequence (Dataset::SelectRows), which joint errors of the move need.
inline void SplitEvenOdd(const Dataset& all, Dataset* even, Dataset* odd) {
  std::vector<int> e, o;
  for (size_t i = 0; i < all.rows.size(); ++i) (i % 2 == 0 ? e : o).push_back(static_cast<int>(i));
  *even = all.SelectRows(e);
  *odd = all.SelectRows(o);
}

}  // namespace kincal::testing
