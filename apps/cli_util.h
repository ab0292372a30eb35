#pragma once
// Small helpers shared by the subcommands.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include "framework/units.h"

namespace kincal::app {

// "1,2,3" -> {1, 2, 3} in the given unit, converted to SI. `what` names the option in messages.
Eigen::VectorXd ParseList(const std::string& text, const Unit& unit, const std::string& what);
std::vector<std::string> SplitComma(const std::string& text);
// A YAML file's root, or an empty node when path is empty. Errors name the file and line.
YAML::Node LoadYamlFile(const std::string& path);

}  // namespace kincal::app
