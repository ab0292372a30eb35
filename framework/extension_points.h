#pragma once
// The entries of the registries of model conventions (models/model_factory.h) and program formats
// (programs/program.h). Declared here, below both, so that the plugin registrar (framework/plugin.h)
// can add to them; ProgramFormat itself is defined in programs/.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "framework/kinematic_model.h"
#include "framework/named_registry.h"

namespace kincal {

class ProgramFormat;

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

struct ProgramFormatEntry {
  std::string name;
  std::string description;              // one line, shown by `kincal methods`
  std::vector<std::string> extensions;  // lower case, without the dot: the files it reads by default
  std::function<std::unique_ptr<ProgramFormat>()> make;
};
using ProgramFormatRegistry = NamedRegistry<ProgramFormatEntry>;

}  // namespace kincal
