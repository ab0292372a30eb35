#include "apps/cli_util.h"

#include "compensators/builtin.h"
#include "estimators/builtin.h"
#include "framework/plugin.h"
#include "models/model_factory.h"
#include "programs/program.h"

#include "framework/atomic_file.h"
#include "framework/error.h"

namespace kincal::app {

Eigen::VectorXd ParseList(const std::string& text, const Unit& unit, const std::string& what) {
  const std::vector<std::string> items = SplitComma(text);
  Eigen::VectorXd out(static_cast<Eigen::Index>(items.size()));
  for (size_t i = 0; i < items.size(); ++i) {
    double v = 0.0;
    if (!ParseDouble(items[i], &v)) {
      ThrowInputError(what + ": expected a comma-separated list of numbers, item " + std::to_string(i + 1) + " is '" +
                      items[i] + "'");
    }
    out[static_cast<Eigen::Index>(i)] = v * unit.to_si;
  }
  return out;
}

YAML::Node LoadYamlFile(const std::string& path) {
  if (path.empty()) return YAML::Node();
  const std::string text = ReadFileToString(path);
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    ThrowInputError(path, e.mark.line + 1, e.mark.column + 1, "invalid YAML: " + e.msg);
  }
}

std::vector<char*> LoadPlugins(int argc, char** argv) {
  std::vector<std::string> paths = PluginPathsFromEnvironment();
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i > 0 && arg == "--plugin") {
      if (i + 1 >= argc) throw std::invalid_argument("--plugin: expected the path of a plugin library");
      paths.push_back(argv[++i]);
    } else if (i > 0 && arg.rfind("--plugin=", 0) == 0) {
      paths.push_back(arg.substr(9));
    } else {
      rest.push_back(argv[i]);
    }
  }
  RegistryRegistrar registrar(&MutableEstimators(), &MutableCompensators(), &MutableModels(), &MutableProgramFormats());
  for (const auto& path : paths) LoadPlugin(path, registrar);
  return rest;
}

}  // namespace kincal::app
