#pragma once
// Plugins: estimators and compensators from a shared library built outside kincal, against an installed
// kincal (find_package(kincal)), loaded at run time by `kincal --plugin PATH`, KINCAL_PLUGIN_PATH and
// kincal.load_plugin(path) in Python. A plugin is one source file (or more) with
//
//   #include "framework/plugin.h"
//   KINCAL_PLUGIN(registrar) {
//     registrar.AddEstimator("my_method", "one line for kincal methods", factory, docs);  // EstimatorRegistry::Factory
//     registrar.AddCompensator("my_comp", "one line", factory, docs);                    // CompensatorRegistry::Factory
//     registrar.AddModel("my_convention", "one line", make, convert);                    // ModelConventionEntry
//     registrar.AddProgramFormat("my_format", "one line", {"ext"}, make);                // ProgramFormatEntry
//   }
// `docs` (optional) documents the options the factory reads, for `kincal methods --options NAME`:
// MyOptions::Table().Docs() with an OptionTable (framework/options.h), or OptionDoc rows by hand.
//
// Layering: this header is in the core, below the Estimator and Compensator interfaces, so it only
// declares them; a plugin includes estimators/estimator.h and compensators/compensator.h to define its
// methods. The registrar is an abstract class: the plugin calls the host's registries through its virtual
// functions, so no symbol of the host (the `kincal` executable or the Python module, each with its own
// static copy of the kincal libraries) has to be visible to the plugin. The plugin links the static
// kincal libraries it uses; it is loaded with RTLD_LOCAL, so its copy stays private to it. Its products
// (estimators, compensators, the models they build) keep pointers into the library: a plugin is never
// unloaded. The version check below makes the two copies the same code.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "framework/extension_points.h"
#include "framework/options.h"
#include "framework/version.h"

namespace kincal {

class Estimator;
class Compensator;

class PluginRegistrar {
 public:
  // The same types as EstimatorRegistry::Factory and CompensatorRegistry::Factory (framework/registry.h).
  using EstimatorFactory = std::function<std::unique_ptr<Estimator>(const YAML::Node& options)>;
  using CompensatorFactory = std::function<std::unique_ptr<Compensator>(const YAML::Node& options)>;

  using ModelFactory = decltype(ModelConventionEntry::make);
  using ModelConversion = decltype(ModelConventionEntry::convert);
  using ProgramFormatFactory = decltype(ProgramFormatEntry::make);

  virtual ~PluginRegistrar() = default;
  // Each throws std::invalid_argument when the name is taken (a built-in one or another plugin's).
  virtual void AddEstimator(const std::string& name, const std::string& description, EstimatorFactory factory,
                            std::vector<OptionDoc> options = {}) = 0;
  virtual void AddCompensator(const std::string& name, const std::string& description, CompensatorFactory factory,
                              std::vector<OptionDoc> options = {}) = 0;
  // A model convention: its models, and the conversion of any model into it (`kincal convert --to`).
  virtual void AddModel(const std::string& name, const std::string& description, ModelFactory make,
                        ModelConversion convert) = 0;
  // A robot program format (programs/program.h), read by `kincal filter` for files of `extensions`.
  virtual void AddProgramFormat(const std::string& name, const std::string& description,
                                std::vector<std::string> extensions, ProgramFormatFactory make) = 0;
};

// The entry point every plugin exports (C linkage: a name dlsym finds). Called with nullptr, it returns
// the kincal version the plugin was built against and registers nothing; called with a registrar, it
// registers the plugin's methods and returns the version again.
#define KINCAL_PLUGIN_ENTRY_POINT "kincal_plugin_entry"
using PluginEntryPoint = const char* (*)(PluginRegistrar* registrar);

template <typename Product>
class Registry;

// The registrar of the command line and the Python module: adds to the registries it is given
// (MutableEstimators(), MutableCompensators(), MutableModels(), MutableProgramFormats()), refusing names
// already taken; a host that gives no model or program-format registry refuses those with one line.
class RegistryRegistrar : public PluginRegistrar {
 public:
  RegistryRegistrar(Registry<Estimator>* estimators, Registry<Compensator>* compensators,
                    ModelRegistry* models = nullptr, ProgramFormatRegistry* formats = nullptr)
      : estimators_(estimators), compensators_(compensators), models_(models), formats_(formats) {}
  void AddEstimator(const std::string& name, const std::string& description, EstimatorFactory factory,
                    std::vector<OptionDoc> options = {}) override;
  void AddCompensator(const std::string& name, const std::string& description, CompensatorFactory factory,
                      std::vector<OptionDoc> options = {}) override;
  void AddModel(const std::string& name, const std::string& description, ModelFactory make,
                ModelConversion convert) override;
  void AddProgramFormat(const std::string& name, const std::string& description, std::vector<std::string> extensions,
                        ProgramFormatFactory make) override;

 private:
  Registry<Estimator>* estimators_;
  Registry<Compensator>* compensators_;
  ModelRegistry* models_;
  ProgramFormatRegistry* formats_;
};

// Loads the shared library at `path` (dlopen RTLD_NOW | RTLD_LOCAL), checks its version and lets it
// register into `registrar`. Throws std::invalid_argument with one line for a missing file, a library
// that does not load, one without the entry point, a version other than KINCAL_VERSION_STRING, or a
// name already taken. Loading the same file twice (by its canonical path) is a no-op the second time.
// Not thread-safe: load plugins before methods run (registries are read without locks).
void LoadPlugin(const std::string& path, PluginRegistrar& registrar);

// The paths of KINCAL_PLUGIN_PATH (colon-separated; empty entries skipped), empty when it is unset.
std::vector<std::string> PluginPathsFromEnvironment();

}  // namespace kincal

#define KINCAL_PLUGIN(registrar)                                                     \
  static void KincalPluginRegister(::kincal::PluginRegistrar& registrar);            \
  extern "C" __attribute__((visibility("default"))) const char* kincal_plugin_entry( \
      ::kincal::PluginRegistrar* kincal_registrar) {                                 \
    if (kincal_registrar) KincalPluginRegister(*kincal_registrar);                   \
    return KINCAL_VERSION_STRING;                                                    \
  }                                                                                  \
  static void KincalPluginRegister(::kincal::PluginRegistrar& registrar)
