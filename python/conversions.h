#pragma once
// Conversions between Python objects and kincal's option and report types, and kincal's errors as
// Python exceptions. Shared by the binding files of the `kincal` module.
#include <string>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

namespace kincal::python {

namespace py = pybind11;

// A dict / list / number / string / bool / None as the YAML node the registries read options from
// (what an options file would hold). Floats keep every digit (repr is the shortest round-trip text).
YAML::Node ToYaml(const py::handle& object);

// A JSON report as plain Python objects (dict, list, float, int, str, bool, None).
py::object ToPython(const nlohmann::json& json);

// kincal.Error (a ValueError): bad input anywhere in kincal (std::invalid_argument, YAML::Exception),
// with the one-line message the command line prints after "kincal: ".
void RegisterErrors(py::module_& m);

// A path given as str or os.PathLike (pathlib.Path), as text.
std::string FsPath(const py::handle& path);

// Throws std::invalid_argument "what: expected N values, got M" (a kincal.Error in Python).
void CheckSize(const std::string& what, long expected, long got);

}  // namespace kincal::python
