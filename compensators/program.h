#pragma once
// CompensateProgram: the targets of a program, compensated in order. The arm reaches each target from
// the one before, so a target without its own previous_command comes from the commands of the one
// before it (joint errors that depend on the move, backlash and approach, are inverted for that move);
// a target that has one (a targets file's from_q columns) keeps it. The first target without one comes
// from nowhere. Used by `kincal compensate`, the Python bindings and the studies' evaluation alike.
#include <vector>

#include "compensators/compensator.h"

namespace kincal {

// One result per target, in order. The compensator must be prepared.
std::vector<CompensationResult> CompensateProgram(const Compensator& compensator,
                                                  const std::vector<CompensationTarget>& targets);

}  // namespace kincal
