#pragma once
// Model conventions by name, as the robot file's `convention` key and `kincal convert --to` name them.
// A convention is its model class (a file pair) and one Register() line in model_factory.cc; plugins
// add theirs through PluginRegistrar::AddModel (framework/plugin.h).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "framework/kinematic_model.h"
#include "framework/named_registry.h"

namespace kincal {

struct ModelConventionEntry {
  std::string name;
  std::string description;  // one line, shown by `kincal methods`
  // A model of the given joints with the convention's nominal (zero) parameters.
  std::function<std::unique_ptr<KinematicModel>(const std::vector<JointType>& joints)> make;
  // Any model in this convention with the same forward kinematics (ConvertModel checks the result and
  // refuses one that differs); throws std::invalid_argument when the convention cannot hold the model.
  std::function<std::unique_ptr<KinematicModel>(const KinematicModel& model)> convert;
  // Conventions of one non-empty family give the same names the same meaning (mdh and hayati): a
  // conversion between them keeps each parameter's free/fixed state; elsewhere everything starts free.
  std::string parameter_family;
};
using ModelRegistry = NamedRegistry<ModelConventionEntry>;

// The built-in conventions (mdh, dh, hayati, poe, urdf) and those plugins added.
const ModelRegistry& Models();
ModelRegistry& MutableModels();

// Models().Get(convention).make(joints); throws std::invalid_argument naming the registered conventions
// for any other name.
std::unique_ptr<KinematicModel> MakeModel(const std::string& convention, const std::vector<JointType>& joints);
// The registered convention names, in alphabetical order.
std::vector<std::string> ModelConventions();

}  // namespace kincal
