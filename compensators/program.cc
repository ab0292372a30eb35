#include "compensators/program.h"

namespace kincal {

void RunProgram(const Compensator& compensator, size_t count, const ProgramTargetBuilder& build,
                const ProgramResultTaker& take) {
  Eigen::VectorXd from;  // the commands the arm was last sent
  for (size_t i = 0; i < count; ++i) {
    CompensationTarget target;
    target.previous_command = from;
    if (!build(i, &target)) continue;
    const CompensationResult result = compensator.Compensate(target);
    from = take(i, target, result);
  }
}

std::vector<CompensationResult> CompensateProgram(const Compensator& compensator,
                                                  const std::vector<CompensationTarget>& targets) {
  std::vector<CompensationResult> results;
  results.reserve(targets.size());
  RunProgram(
      compensator, targets.size(),
      [&](size_t i, CompensationTarget* target) {
        Eigen::VectorXd from = std::move(target->previous_command);
        *target = targets[i];
        if (target->previous_command.size() == 0) target->previous_command = std::move(from);
        return true;
      },
      [&](size_t, const CompensationTarget&, const CompensationResult& result) {
        results.push_back(result);
        return result.q_command;
      });
  return results;
}

}  // namespace kincal
