#pragma once
// The UR10 of ../shared/data/ur10_ipa2021 (data README), read straight from the source's CSV for tests and
// benchmarks (never copied into the project), and the robot file model selection chooses from.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "robot/robot.h"
#include "tests/support/test_util.h"

namespace kincal::testing {

// The source's CSV (';' separators, ',' decimal mark): joints (rad) and measurement_x/y/z (mm).
inline bool LoadUr10Series(const std::string& path, Dataset* data) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ';');) header.push_back(line);
  const std::vector<std::string> want = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                         "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint",
                                         "measurement_x",      "measurement_y",       "measurement_z"};
  std::vector<int> column;
  for (const auto& w : want)
    column.push_back(static_cast<int>(std::find(header.begin(), header.end(), w) - header.begin()));
  data->dof = 6;
  while (std::getline(in, line)) {
    std::vector<double> f;
    for (std::stringstream ss(line); std::getline(ss, line, ';');) {
      std::replace(line.begin(), line.end(), ',', '.');
      f.push_back(std::atof(line.c_str()));
    }
    Measurement m;
    m.q = Eigen::VectorXd(6);
    for (int j = 0; j < 6; ++j) m.q[j] = f.at(column[j]);
    for (int k = 0; k < 3; ++k) m.p[k] = f.at(column[6 + k]) * 1e-3;
    data->rows.push_back(m);
  }
  return true;
}

// ur10_dh.yaml with a 100 mm tool (the protocol of the table in docs/guide/real_data.md), the UR10's joint
// speeds and the first `groups`
// joint-error groups of the richest file, in model selection's order: gravity 2-5, harmonic orders 1 and 2
// on joints 1-6, backlash 1-6, approach 1-6 (22 groups in all).
inline Robot Ur10Rich(int groups) {
  Robot robot = LoadExampleRobot("ur10_dh.yaml");
  robot.model().SetTool(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1)));
  robot.velocity_limits = (Eigen::VectorXd(6) << 120, 120, 180, 180, 180, 180).finished() * (M_PI / 180);
  using T = JointErrorTerm::Type;
  std::vector<JointErrorTerm> all;
  const auto add = [&](T type, int joint) {
    JointErrorTerm t;
    t.type = type;
    t.joint = joint;
    if (type == T::kHarmonic) t.orders = {1, 2};
    all.push_back(t);
  };
  for (int j = 1; j <= 4; ++j) add(T::kGravity, j);
  for (T type : {T::kHarmonic, T::kBacklash, T::kApproach})
    for (int j = 0; j < 6; ++j) add(type, j);
  for (int g = 0; g < groups && g < static_cast<int>(all.size()); ++g) robot.joint_errors.terms.push_back(all[g]);
  robot.joint_errors.Bind(robot.model());
  return robot;
}

}  // namespace kincal::testing
