#include "python/conversions.h"

#include <stdexcept>

namespace kincal::python {

YAML::Node ToYaml(const py::handle& object) {
  if (object.is_none()) return YAML::Node();
  // bool before int: True is an int in Python.
  if (py::isinstance<py::bool_>(object)) return YAML::Node(object.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::int_>(object)) return YAML::Node(py::str(object).cast<std::string>());
  if (py::isinstance<py::float_>(object)) return YAML::Node(py::repr(object).cast<std::string>());
  if (py::isinstance<py::str>(object)) return YAML::Node(object.cast<std::string>());
  if (py::isinstance<py::dict>(object)) {
    YAML::Node node(YAML::NodeType::Map);
    for (const auto& kv : object.cast<py::dict>()) node[py::str(kv.first).cast<std::string>()] = ToYaml(kv.second);
    return node;
  }
  if (py::isinstance<py::list>(object) || py::isinstance<py::tuple>(object)) {
    YAML::Node node(YAML::NodeType::Sequence);
    for (const auto& item : object) node.push_back(ToYaml(item));
    return node;
  }
  // numpy scalars and arrays: through their Python equivalents.
  if (py::hasattr(object, "tolist")) return ToYaml(object.attr("tolist")());
  throw std::invalid_argument("options: cannot use a " + py::str(object.get_type()).cast<std::string>() +
                              " as an option value (expected dict, list, number, string or bool)");
}

py::object ToPython(const nlohmann::json& json) {
  switch (json.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(json.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(json.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(json.get<uint64_t>());
    case nlohmann::json::value_t::number_float:
      return py::float_(json.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(json.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const auto& item : json) list.append(ToPython(item));
      return std::move(list);
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, value] : json.items()) dict[py::str(key)] = ToPython(value);
      return std::move(dict);
    }
    default:
      return py::none();
  }
}

void RegisterErrors(py::module_& m) {
  static py::exception<std::invalid_argument> error(m, "Error", PyExc_ValueError);
  error.doc() = "Bad input to kincal: the one-line message (file:line:column: what) of the command line.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::invalid_argument& e) {
      error(e.what());
    } catch (const YAML::Exception& e) {
      error(e.what());
    }
  });
}

std::string FsPath(const py::handle& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

void CheckSize(const std::string& what, long expected, long got) {
  if (expected != got) {
    throw std::invalid_argument(what + ": expected " + std::to_string(expected) + " values, got " +
                                std::to_string(got));
  }
}

}  // namespace kincal::python
