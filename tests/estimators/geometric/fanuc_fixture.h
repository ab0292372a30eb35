#pragma once
// The FANUC R-2000i-class sweeps of ../shared/data/fanuc_boby2021 (sweeps.csv) as a kincal dataset, and
// the same protocol in simulation: one sweep per joint, 6 stops, three reflectors measured at every stop.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "framework/dataset.h"

namespace kincal::testing {

// sweeps.csv (`row, joint, q1..q6` in deg, `s1x..s3z` in mm) in kincal's dataset format: one row per
// reflector (SMR1..3) and stop, in measurement order, with the sweep's joint. `split`: the 1st, 3rd and
// 5th stop of every sweep train, the others test (the reference's held-out protocol); false: no split.
// Returns false when the file cannot be read.
inline bool FanucSweepsCsv(const std::string& path, bool split, std::string* csv) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  std::getline(in, line);  // header
  std::ostringstream out;
  out << "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,sweep,marker" << (split ? ",split" : "") << "\n";
  int previous_joint = 0, stop = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    if (f.size() != 17) return false;
    const int joint = std::stoi(f[1]);
    stop = joint == previous_joint ? stop + 1 : 0;
    previous_joint = joint;
    for (int s = 0; s < 3; ++s) {
      for (int i = 0; i < 6; ++i) out << f[2 + i] << ",";
      out << f[8 + 3 * s] << "," << f[9 + 3 * s] << "," << f[10 + 3 * s] << "," << joint << ",SMR" << s + 1;
      if (split) out << "," << (stop % 2 == 0 ? "train" : "test");
      out << "\n";
    }
  }
  *csv = out.str();
  return true;
}

}  // namespace kincal::testing
