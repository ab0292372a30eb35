#pragma once
// The loop over a program's targets, compensated in order. The arm reaches each target from the one
// before, so a target without its own previous_command comes from the commands of the one before it
// (joint errors that depend on the move, backlash and approach, are inverted for that move); a target
// that has one (a targets file's from_q columns) keeps it. The first target without one comes from
// nowhere. CompensateProgram is that loop over given targets (`kincal compensate`, the Python bindings
// and the studies' evaluation); RunProgram is the same loop for a caller that builds each target when
// its turn comes and decides what the arm is commanded (programs/filter.cc: the seed is the controller's
// solution nearest the previous target's, and a target not reached is sent as written).
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "compensators/compensator.h"

namespace kincal {

// Builds target i. *target arrives with previous_command = where the arm comes from (empty for the
// first target, or after none was sent); the builder may keep or replace it. false: target i is not
// compensated, and the arm does not move.
using ProgramTargetBuilder = std::function<bool(size_t i, CompensationTarget* target)>;
// Takes the result of target i and returns the commands the arm is actually sent there (where it comes
// from for the next target).
using ProgramResultTaker =
    std::function<Eigen::VectorXd(size_t i, const CompensationTarget& target, const CompensationResult& result)>;

// Targets 0..count-1 in order. The compensator must be prepared.
void RunProgram(const Compensator& compensator, size_t count, const ProgramTargetBuilder& build,
                const ProgramResultTaker& take);

// One result per target, in order; each is sent as computed (q_command).
std::vector<CompensationResult> CompensateProgram(const Compensator& compensator,
                                                  const std::vector<CompensationTarget>& targets);

}  // namespace kincal
