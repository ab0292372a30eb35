#pragma once
// The targets of a targets file: a dataset with x, y, z, optionally qw..qz (without them: position-only
// targets), optionally the controller's nominal solution q1..qN as seeds and from_q1..from_qN.
#include <vector>

#include "compensators/compensator.h"
#include "framework/dataset.h"

namespace kincal {

// Throws std::invalid_argument naming the file for columns that have no meaning for targets (enc, sweep,
// marker, session, split), a seed count other than the robot's `dof`, or no rows.
std::vector<CompensationTarget> CompensationTargetsFrom(const Dataset& data, int dof);

}  // namespace kincal
