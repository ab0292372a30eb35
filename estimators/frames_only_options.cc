#include "estimators/frames_only_options.h"

#include <string>

namespace kincal {

YAML::Node FramesOnlyOptions(const Robot& robot) {
  YAML::Node options;
  for (int j = 1; j <= robot.dof(); ++j) options["fixed"].push_back("joint_" + std::to_string(j));
  if (!robot.joint_errors.terms.empty()) options["fixed"].push_back("joint_errors");
  options["identify_ratios"] = false;
  return options;
}

}  // namespace kincal
