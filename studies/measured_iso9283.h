#pragma once
// ISO 9283:1998 pose accuracy (AP, section 7.2.1) and repeatability (RP, section 7.2.2) of a real arm
// from measured rows: the arm visited some commanded poses several times (cycles), and an instrument
// measured every visit. The formulas are ComputeIso9283's (studies/validation.h).
//
// Visits. The controller's own model (`controller`, the nominal robot) maps a row's joint readings to
// the pose it believes the arm is at, in the robot's base frame: the commanded pose, to within the servo
// and encoder resolution. Rows of one session whose controller poses lie within `tolerance.length` (m)
// and `tolerance.angle` (rad) of a pose's first visit are visits of that pose, in measurement order.
// (Joint readings alone would split visits at a wrist singularity, where joints 4 and 6 trade angle and
// the pose stays.) Poses with at least `min_cycles` visits are scored, numbered P1, P2, ... in the order
// of their first visit.
//
// Commanded pose in the measurement frame. The commanded pose is in the robot's base frame and the
// instrument measures in its own, so a registration is needed: the commanded pose of a pose is where
// `model` puts it, the mean of its predictions over the visits (positions averaged; rotations averaged as
// rotation vectors about the first). With the study's "before" (the nominal geometry with only base and
// tool or markers fitted to the training rows) this is the controller's own pose registered into the
// instrument's frame by a best fit of base and tool; with an identified robot it is what a compensator
// using that robot commands, so AP is then the accuracy left after compensation (to first order:
// |mean(measured - predicted)|). RP uses the measured poses alone and does not depend on the model.
//
// Attained poses: the measured rows. Orientation (AP_a/b/c, RP_a/b/c) only where every visit of the pose
// measured one; otherwise those fields are NaN.
#include <cmath>
#include <vector>

#include "framework/dataset.h"
#include "robot/robot.h"
#include "studies/validation.h"

namespace kincal {

struct MeasuredIsoPose {
  int pose = 0;           // 1-based, in order of first visit
  std::vector<int> rows;  // the visits, indices into the dataset, in measurement order
  Iso9283PoseStats stats;
};

struct VisitTolerance {
  double length = 0.2e-3;             // m
  double angle = 0.1 * M_PI / 180.0;  // rad
};

// Visits of commanded poses (see above); every group, also those visited once.
std::vector<std::vector<int>> GroupVisits(const Robot& controller, const Dataset& data,
                                          const VisitTolerance& tolerance);

// The ISO 9283 characteristics of every pose of `data` visited at least `min_cycles` (>= 2) times.
std::vector<MeasuredIsoPose> MeasuredIso9283(const Robot& controller, const Robot& model, const Dataset& data,
                                             const VisitTolerance& tolerance, int min_cycles);

}  // namespace kincal
