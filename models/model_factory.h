#pragma once
// Model conventions by name, as the robot file's `convention` key and `kincal convert --to` name them.
// A convention is its model class (a file pair) and one Register() line in model_factory.cc; plugins
// add theirs through PluginRegistrar::AddModel (framework/plugin.h).
#include <memory>
#include <string>
#include <vector>

#include "framework/extension_points.h"

namespace kincal {

// ModelConventionEntry and ModelRegistry: framework/extension_points.h.

// The built-in conventions (mdh, dh, hayati, poe, urdf) and those plugins added.
const ModelRegistry& Models();
ModelRegistry& MutableModels();

// Models().Get(convention).make(joints); throws std::invalid_argument naming the registered conventions
// for any other name.
std::unique_ptr<KinematicModel> MakeModel(const std::string& convention, const std::vector<JointType>& joints);
// The registered convention names, in alphabetical order.
std::vector<std::string> ModelConventions();

}  // namespace kincal
