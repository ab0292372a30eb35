#include "compensators/program.h"

namespace kincal {

std::vector<CompensationResult> CompensateProgram(const Compensator& compensator,
                                                  const std::vector<CompensationTarget>& targets) {
  std::vector<CompensationResult> results;
  results.reserve(targets.size());
  for (const CompensationTarget& given : targets) {
    if (given.previous_command.size() > 0 || results.empty()) {
      results.push_back(compensator.Compensate(given));
      continue;
    }
    CompensationTarget target = given;
    target.previous_command = results.back().q_command;
    results.push_back(compensator.Compensate(target));
  }
  return results;
}

}  // namespace kincal
