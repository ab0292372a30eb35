#pragma once
// Measured data as plain whitespace tables, the way tracker software and robot controllers export it:
// one table of joint readings (one column per joint) and one x y z table per marker, row i of every table
// being pose i in measurement order (e.g. ../shared/data/irb120_faro). The result is a kincal Dataset with
// one row per (pose, marker), markers in the order given, so a pose's rows stay together and the measurement
// sequence (Dataset::PreviousPoses) is the tables' row order.
#include <string>
#include <utility>
#include <vector>

#include "framework/dataset.h"
#include "framework/units.h"

namespace kincal {

struct PoseTables {
  std::string joints;                                       // path
  std::vector<std::pair<std::string, std::string>> positions;  // marker name -> path
  Unit length_unit = {"mm", 1e-3};
  Unit angle_unit = {"deg", M_PI / 180.0};
};

// Throws std::invalid_argument "file:line:col: what" for an unreadable file, a non-number, a row with
// another number of columns, or tables of different lengths.
Dataset ReadPoseTables(const PoseTables& tables, int dof);

}  // namespace kincal
