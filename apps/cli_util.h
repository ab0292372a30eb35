#pragma once
// Small helpers shared by the subcommands.
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include "framework/method_options.h"
#include "framework/short_line.h"
#include "framework/units.h"

namespace kincal::app {

// "1,2,3" -> {1, 2, 3} in the given unit, converted to SI. `what` names the option in messages.
Eigen::VectorXd ParseList(const std::string& text, const Unit& unit, const std::string& what);
// A YAML file's root, or an empty node when path is empty. Errors name the file and line.
YAML::Node LoadYamlFile(const std::string& path);
// Runs `body`, which reads or uses the file `path`; a std::invalid_argument it throws is rethrown with
// the file's name in front unless the message starts with it already (the options reader knows line and
// column but not the file; an estimator refusing a dataset knows neither).
template <typename Body>
auto NamingFile(const std::string& path, Body&& body) {
  try {
    return body();
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    if (path.empty() || message.compare(0, path.size(), path) == 0) throw;
    throw std::invalid_argument(path + ": " + message);
  }
}

// Loads the plugins of KINCAL_PLUGIN_PATH, then those named by `--plugin PATH` or `--plugin=PATH`
// anywhere on the command line (before any subcommand's own options are parsed, so that every subcommand
// sees their methods), into the registries. Returns the arguments without the --plugin options. Throws
// std::invalid_argument (one line) for a plugin that cannot be loaded (framework/plugin.h).
std::vector<char*> LoadPlugins(int argc, char** argv);

}  // namespace kincal::app
