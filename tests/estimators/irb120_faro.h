#pragma once
// The ABB IRB 120 laser-tracker set of ../shared/data/irb120_faro (data README): 982 processed poses,
// joints read back from the controller (deg) and reflector positions (mm) in the tracker frame. Used by
// tests and benchmarks only; read in place, never copied into the project.
#include <fstream>
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "framework/pose_tables.h"
#include "robot/robot_file.h"

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

// The processed tables of reflectors `smrs` (1..3) through the project's reader (framework/pose_tables.h),
// in measurement order, one row per pose and reflector (markers "SMR1".. in the order given); false when
// the data folder is absent. The processed files are measured_joints.txt with 18 poses removed (outliers
// and unmeasured rows), but the arm made those moves: the unfiltered readings give every pose the one it
// was reached from (16 poses follow a removed one).
inline bool LoadIrb120FaroReflectors(const std::string& folder, const std::vector<int>& smrs, Dataset* data) {
  PoseTables tables;
  tables.joints = folder + "/processed_joints.txt";
  if (!std::ifstream(tables.joints).good()) return false;
  tables.sequence = folder + "/measured_joints.txt";
  for (int smr : smrs) {
    tables.positions.emplace_back("SMR" + std::to_string(smr),
                                  folder + "/processed_SMR_" + std::to_string(smr) + ".txt");
  }
  *data = ReadPoseTables(tables, 6);
  data->source = folder;
  return true;
}

// Reflector `smr` (1..3) alone as the tool origin (rows without a marker name: the robot's tool is the
// reflector), as above.
inline bool LoadIrb120Faro(const std::string& folder, int smr, Dataset* data) {
  if (!LoadIrb120FaroReflectors(folder, {smr}, data)) return false;
  for (Measurement& m : data->rows) m.marker.clear();
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

// Reflector `smr` as above, split into even rows (train) and odd rows (test); false when the data
// folder is absent.
inline bool LoadIrb120FaroSplit(const std::string& folder, int smr, Dataset* train, Dataset* test) {
  Dataset all;
  if (!LoadIrb120Faro(folder, smr, &all)) return false;
  SplitEvenOdd(all, train, test);
  return true;
}

}  // namespace kincal::testing
