#pragma once
// What the command line and the Python module both read the same way: method lists ("a,b") and the
// options of each method of a pipeline.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace kincal {

// "a,b,c" -> {"a", "b", "c"} (empty items kept): method pipelines and lists on the command line.
std::vector<std::string> SplitComma(const std::string& text);

// The options of each method of a pipeline, as `kincal identify --options` and Python's identify read
// them: a map keyed by method names (a method it leaves out gets a null node: its defaults), or, for one
// method, that method's options directly. `where` names the source in messages: a file (line 1, the
// root) or, with line 0, an argument ("options"). Throws std::invalid_argument for a root that is not a
// map, or options not keyed by method name when there are several methods.
std::vector<YAML::Node> OptionsPerMethod(const YAML::Node& root, const std::vector<std::string>& methods,
                                         const std::string& where, int line = 1);

}  // namespace kincal
