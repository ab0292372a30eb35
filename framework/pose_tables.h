#pragma once
// Measured data as plain whitespace tables, the way tracker software and robot controllers export it:
// one table of joint readings (one column per joint) and one x y z table per marker, row i of every table
// being pose i in measurement order (e.g. ../shared/data/irb120_faro). The result is a kincal Dataset with
// one row per (pose, marker), markers in the order given, so a pose's rows stay together and the measurement
// sequence (Dataset::PreviousPoses) is the tables' row order.
//
// Filtered tables. Tracker data are often published after outliers and unmeasured poses were removed
// (irb120_faro: 982 of 1000 poses), but the arm still made the removed moves: a kept pose that followed a
// removed one was reached from the removed pose, not from the kept pose before it, and joint errors of the
// move (approach, backlash) must know that. Given the unfiltered joint readings (`sequence`: every pose the
// arm went to, in order), each pose of `joints` is found in it (the earliest match after the previous
// pose's, every joint within 1e-6 of the angle unit) and its previous pose is its predecessor there (the
// last earlier pose with other joint values); rows whose previous pose is not the one before them in
// `joints` carry it in from_q, as a dataset file of filtered rows would (DatasetToCsv writes it back).
#include <string>
#include <utility>
#include <vector>

#include "framework/dataset.h"
#include "framework/units.h"

namespace kincal {

struct PoseTables {
  std::string joints;                                          // path
  std::vector<std::pair<std::string, std::string>> positions;  // marker name -> path
  std::string sequence;  // path of the unfiltered joint readings (see above); "": `joints` is the whole sequence
  Unit length_unit = {"mm", 1e-3};
  Unit angle_unit = {"deg", M_PI / 180.0};
};

// Throws std::invalid_argument "file:line:col: what" for an unreadable file, a non-number, a row with
// another number of columns, tables of different lengths, or a pose of `joints` not found in `sequence`
// after the previous pose's match.
Dataset ReadPoseTables(const PoseTables& tables, int dof);

}  // namespace kincal
