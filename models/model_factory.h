#pragma once
// Models by convention name, as the robot file's `convention` key names them.
#include <memory>
#include <string>
#include <vector>

#include "framework/kinematic_model.h"

namespace kincal {

// "mdh", "dh", "hayati", "poe" or "urdf" (ModelConventions()); throws std::invalid_argument naming the
// known conventions for any other name.
std::unique_ptr<KinematicModel> MakeModel(const std::string& convention, const std::vector<JointType>& joints);
std::vector<std::string> ModelConventions();

}  // namespace kincal
