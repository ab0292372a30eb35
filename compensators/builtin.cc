// The registry of every compensator kincal knows. Adding one: one Register() call here, its target in
// compensators/CMakeLists.txt.
#include "compensators/baseline/none_compensator.h"
#include "framework/compensator.h"

namespace kincal {
namespace {

template <typename T>
CompensatorRegistry::Factory FactoryOf() {
  return [](const YAML::Node& node) -> std::unique_ptr<Compensator> {
    const typename T::Options options = T::Options::FromYaml(node);
    std::string why;
    if (!options.IsValid(&why)) throw std::invalid_argument("invalid options: " + why);
    return std::make_unique<T>(options);
  };
}

CompensatorRegistry MakeRegistry() {
  CompensatorRegistry r;
  r.Register({"none", "the controller's nominal joints, unchanged (baseline)", FactoryOf<NoneCompensator>(), true, ""});
  return r;
}

}  // namespace

const CompensatorRegistry& Compensators() {
  static const CompensatorRegistry registry = MakeRegistry();
  return registry;
}

}  // namespace kincal
