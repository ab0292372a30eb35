// Methods from outside kincal in Python: estimators and compensators written in Python
// (register_estimator, register_compensator) and C++ plugins (load_plugin, framework/plugin.h), added to
// the module's registries, so that identify, compensate and run_study use them beside the built-in ones.
//
// Threads and the GIL: kincal releases the GIL while it works (identify, compensate, run_study), and a
// study runs its work items on a thread pool. A Python method's factory, estimate(), prepare(),
// compensate() and destruction take the GIL: Python methods run one at a time (one thread at a time runs
// Python code), beside C++ methods that run in parallel on the other threads.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "compensators/builtin.h"
#include "estimators/builtin.h"
#include "framework/error.h"
#include "framework/plugin.h"
#include "models/model_factory.h"
#include "python/bindings.h"
#include "python/conversions.h"

namespace kincal::python {
namespace {

// A Python exception as a C++ one, its message kept: the study fails that work item with it, identify
// and compensate raise it again in Python (RuntimeError). Called with the GIL held.
[[noreturn]] void Rethrow(py::error_already_set& e) {
  // The type and the message, without the traceback pybind11 appends to what().
  std::string message = py::str(e.value());
  if (e.type()) message = py::str(e.type().attr("__name__")).cast<std::string>() + ": " + message;
  PyErr_Clear();
  throw std::runtime_error(OneLine(message));
}

// A Python object owned by C++ code that may drop it on any thread: released with the GIL, or leaked
// when the interpreter is gone (registries live until the process ends).
struct PyRef {
  explicit PyRef(py::object o) : object(std::move(o)) {}
  ~PyRef() {
    if (!Py_IsInitialized()) {
      object.release();
      return;
    }
    py::gil_scoped_acquire gil;
    object = py::object();
  }
  py::object object;
};

nlohmann::json ToJson(const py::handle& object) {
  const py::object dumps = py::module_::import("json").attr("dumps");
  return nlohmann::json::parse(
      dumps(object, py::arg("default") = py::cpp_function([](py::handle h) { return py::str(h); }))
          .cast<std::string>());
}

// Options as the factory sees them: a dict (empty when none), numbers and booleans as such, the rest text.
py::object YamlToPython(const YAML::Node& node) {
  if (!node || node.IsNull()) return py::dict();
  if (node.IsMap()) {
    py::dict d;
    for (const auto& kv : node) d[py::str(kv.first.as<std::string>())] = YamlToPython(kv.second);
    return std::move(d);
  }
  if (node.IsSequence()) {
    py::list l;
    for (const auto& item : node) l.append(YamlToPython(item));
    return std::move(l);
  }
  const std::string text = node.as<std::string>();
  if (node.Tag() != "!") {  // an unquoted scalar: a number or a boolean when it reads as one
    if (text == "true" || text == "false") return py::bool_(text == "true");
    try {
      size_t used = 0;
      const long long i = std::stoll(text, &used);
      if (used == text.size()) return py::int_(i);
    } catch (const std::exception&) {
    }
    try {
      size_t used = 0;
      const double x = std::stod(text, &used);
      if (used == text.size()) return py::float_(x);
    } catch (const std::exception&) {
    }
  }
  return py::str(text);
}

EstimationStatus EstimationStatusFrom(const std::string& text) {
  for (auto s : {EstimationStatus::kConverged, EstimationStatus::kIterationLimit, EstimationStatus::kFailed}) {
    if (ToString(s) == text) return s;
  }
  throw std::invalid_argument("unknown estimation status '" + text + "' (converged, iteration_limit, failed)");
}

CompensationStatus CompensationStatusFrom(const std::string& text) {
  for (auto s : {CompensationStatus::kConverged, CompensationStatus::kIterationLimit, CompensationStatus::kSingular,
                 CompensationStatus::kUnreachable, CompensationStatus::kOutOfLimits, CompensationStatus::kFailed}) {
    if (ToString(s) == text) return s;
  }
  throw std::invalid_argument("unknown compensation status '" + text + "'");
}

double NumberOr(const nlohmann::json& j, const char* key, double fallback) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

// The keys of EstimationReport::ToJson that an estimator sets itself (the rest Estimate() fills).
void ReadReportKeys(const nlohmann::json& j, EstimationReport* report) {
  report->condition_number = NumberOr(j, "condition_number", NAN);
  if (j.contains("parameters") && j["parameters"].is_array()) {
    for (const auto& p : j["parameters"]) {
      ParameterEstimate e;
      e.name = p.value("name", "");
      e.unit = p.value("unit", "");
      e.nominal = NumberOr(p, "nominal", NAN);
      e.value = NumberOr(p, "value", NAN);
      e.stddev = NumberOr(p, "stddev", NAN);
      e.prior_sd = NumberOr(p, "prior_sd", NAN);
      e.data_sd = NumberOr(p, "data_sd", NAN);
      e.data_share = NumberOr(p, "data_share", NAN);
      e.weak = p.value("weak", false);
      e.free = p.value("free", true);
      e.note = p.value("note", "");
      report->parameters.push_back(e);
    }
  }
  if (j.contains("fixed_parameters")) report->fixed_parameters = j["fixed_parameters"].get<std::vector<std::string>>();
  if (j.contains("warnings")) report->warnings = j["warnings"].get<std::vector<std::string>>();
  report->details = j.contains("details") ? j["details"] : j;
}

class PythonEstimator final : public Estimator {
 public:
  PythonEstimator(std::string name, py::object instance)
      : name_(std::move(name)), instance_(std::make_unique<PyRef>(std::move(instance))) {}
  std::string name() const override { return name_; }

 private:
  // estimate(start: Robot, data: Dataset) -> (Robot, dict). The dict has the keys of an estimation
  // report (kincal.identify's), all optional: status ("converged", "iteration_limit", "failed"; default
  // converged), message, iterations, condition_number, parameters, fixed_parameters, warnings, details
  // (default: the whole dict).
  void DoEstimate(const Robot& start, const Robot& /*controller*/, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override {
    py::gil_scoped_acquire gil;
    try {
      const py::object out = instance_->object.attr("estimate")(start, data);
      const py::tuple pair = out.cast<py::tuple>();
      if (pair.size() != 2) throw std::invalid_argument("estimate() must return (Robot, dict)");
      *identified = pair[0].cast<Robot>();
      const py::dict info = pair[1].is_none() ? py::dict() : pair[1].cast<py::dict>();
      report->status = EstimationStatus::kConverged;
      if (info.contains("status")) report->status = EstimationStatusFrom(py::str(info["status"]));
      if (info.contains("message")) report->message = py::str(info["message"]);
      if (info.contains("iterations")) report->iterations = info["iterations"].cast<int>();
      ReadReportKeys(ToJson(info), report);
    } catch (py::error_already_set& e) {
      Rethrow(e);
    } catch (const py::cast_error& e) {
      throw std::runtime_error(name_ + ": estimate() must return (Robot, dict): " + e.what());
    }
  }

  std::string name_;
  std::unique_ptr<PyRef> instance_;
};

class PythonCompensator final : public Compensator {
 public:
  PythonCompensator(std::string name, py::object instance)
      : name_(std::move(name)), instance_(std::make_unique<PyRef>(std::move(instance))) {}
  std::string name() const override { return name_; }

 private:
  // prepare(nominal: Robot, identified: Robot), when the object has one: its offline stage.
  void DoPrepare() override {
    py::gil_scoped_acquire gil;
    try {
      if (py::hasattr(instance_->object, "prepare")) instance_->object.attr("prepare")(nominal(), identified());
    } catch (py::error_already_set& e) {
      Rethrow(e);
    }
  }
  // compensate(target: 4x4 array T_meas_tool, seed: array) -> (q array, status str).
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override {
    py::gil_scoped_acquire gil;
    try {
      const Eigen::Matrix4d T = target.T_meas_tool.matrix();
      const py::tuple pair = instance_->object.attr("compensate")(T, seed).cast<py::tuple>();
      if (pair.size() != 2) throw std::invalid_argument("compensate() must return (q, status)");
      result->q_actual = pair[0].cast<Eigen::VectorXd>();
      result->report.status = CompensationStatusFrom(py::str(pair[1]));
    } catch (py::error_already_set& e) {
      Rethrow(e);
    } catch (const py::cast_error& e) {
      throw std::runtime_error(name_ + ": compensate() must return (q array, status str): " + e.what());
    }
    if (result->q_actual.size() != seed.size()) {
      throw std::runtime_error(name_ + ": compensate() returned " + std::to_string(result->q_actual.size()) +
                               " joints, expected " + std::to_string(seed.size()));
    }
  }

  std::string name_;
  std::unique_ptr<PyRef> instance_;
};

// The registry's factory for a Python factory: factory(options: dict) -> object, with the GIL.
template <typename Product, typename Wrapper>
std::function<std::unique_ptr<Product>(const YAML::Node&)> FactoryOf(const std::string& name, py::object factory) {
  auto ref = std::make_shared<PyRef>(std::move(factory));
  return [name, ref](const YAML::Node& options) -> std::unique_ptr<Product> {
    py::gil_scoped_acquire gil;
    try {
      py::object instance = ref->object(YamlToPython(options));
      if (instance.is_none()) throw std::invalid_argument(name + ": the factory returned None");
      return std::make_unique<Wrapper>(name, std::move(instance));
    } catch (py::error_already_set& e) {
      Rethrow(e);
    }
  };
}

// register_estimator and register_compensator: a callable factory, added through the registrar.
template <typename Add>
void RegisterPython(const char* function, const py::object& factory, Add add) {
  if (!PyCallable_Check(factory.ptr()))
    throw std::invalid_argument(std::string(function) + ": factory is not callable");
  RegistryRegistrar registrar(&MutableEstimators(), &MutableCompensators());
  add(&registrar);
}

}  // namespace

void BindPlugins(py::module_& m) {
  m.def(
      "register_estimator",
      [](const std::string& name, py::object factory, const std::string& description) {
        RegisterPython("register_estimator", factory, [&](RegistryRegistrar* registrar) {
          registrar->AddEstimator(name, description.empty() ? "Python estimator" : description,
                                  FactoryOf<Estimator, PythonEstimator>(name, factory));
        });
      },
      py::arg("name"), py::arg("factory"), py::arg("description") = "",
      "Adds an estimator written in Python: factory(options: dict) returns an object with estimate(start: Robot, "
      "data: Dataset) -> (Robot, dict). It runs in identify and run_study beside the C++ estimators (one Python "
      "call at a time: the GIL); an exception in it fails that work item with its message.");
  m.def(
      "register_compensator",
      [](const std::string& name, py::object factory, const std::string& description) {
        RegisterPython("register_compensator", factory, [&](RegistryRegistrar* registrar) {
          registrar->AddCompensator(name, description.empty() ? "Python compensator" : description,
                                    FactoryOf<Compensator, PythonCompensator>(name, factory));
        });
      },
      py::arg("name"), py::arg("factory"), py::arg("description") = "",
      "Adds a compensator written in Python: factory(options: dict) returns an object with compensate(target: 4x4 "
      "array, seed: array) -> (q array, status str) and optionally prepare(nominal: Robot, identified: Robot).");
  m.def(
      "load_plugin",
      [](const py::object& path) {
        // The module reads no robot programs: a plugin's program format is refused here with one line.
        RegistryRegistrar registrar(&MutableEstimators(), &MutableCompensators(), &MutableModels());
        LoadPlugin(FsPath(path), registrar);
      },
      py::arg("path"),
      "Loads a C++ plugin (framework/plugin.h) into this module's registries, as `kincal --plugin PATH`.");
}

}  // namespace kincal::python
