#include "framework/plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <type_traits>

#include "framework/error.h"
#include "framework/registry.h"

namespace kincal {

static_assert(std::is_same_v<PluginRegistrar::EstimatorFactory, Registry<Estimator>::Factory>);
static_assert(std::is_same_v<PluginRegistrar::CompensatorFactory, Registry<Compensator>::Factory>);

void RegistryRegistrar::AddEstimator(const std::string& name, const std::string& description,
                                     EstimatorFactory factory, std::vector<OptionDoc> options) {
  if (name.empty()) throw std::invalid_argument("an estimator needs a name");
  if (!factory) throw std::invalid_argument("estimator '" + name + "': no factory");
  if (estimators_->IsRegistered(name)) {
    throw std::invalid_argument("estimator name '" + name + "' is taken (" + estimators_->Get(name).description + ")");
  }
  estimators_->Register({name, description, std::move(factory), std::move(options)});
}

void RegistryRegistrar::AddCompensator(const std::string& name, const std::string& description,
                                       CompensatorFactory factory, std::vector<OptionDoc> options) {
  if (name.empty()) throw std::invalid_argument("a compensator needs a name");
  if (!factory) throw std::invalid_argument("compensator '" + name + "': no factory");
  if (compensators_->IsRegistered(name)) {
    throw std::invalid_argument("compensator name '" + name + "' is taken (" + compensators_->Get(name).description +
                                ")");
  }
  compensators_->Register({name, description, std::move(factory), std::move(options)});
}

void RegistryRegistrar::AddModel(const std::string& name, const std::string& description, ModelFactory make,
                                 ModelConversion convert) {
  if (!models_) throw std::invalid_argument("model convention '" + name + "': this host takes no model conventions");
  if (!make || !convert) throw std::invalid_argument("model convention '" + name + "': no factory or conversion");
  // A plugin's convention shares no parameter family: its names are its own.
  models_->Register({name, description, std::move(make), std::move(convert), ""});
}

void RegistryRegistrar::AddProgramFormat(const std::string& name, const std::string& description,
                                         std::vector<std::string> extensions, ProgramFormatFactory make) {
  if (!formats_) throw std::invalid_argument("program format '" + name + "': this host takes no program formats");
  if (!make) throw std::invalid_argument("program format '" + name + "': no factory");
  formats_->Register({name, description, std::move(extensions), std::move(make)});
}

void LoadPlugin(const std::string& path, PluginRegistrar& registrar) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw std::invalid_argument("plugin " + path + ": no such file");
  const std::string canonical = fs::canonical(path, ec).string();
  // Registrars differ (the command line's, the Python module's); a file is loaded once per registrar.
  static std::set<std::pair<const PluginRegistrar*, std::string>> loaded;
  if (loaded.count({&registrar, canonical})) return;
  // RTLD_LOCAL: the plugin's own copy of the kincal libraries stays private to it (framework/plugin.h).
  void* handle = dlopen(canonical.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw std::invalid_argument("plugin " + path + ": cannot load: " + OneLine(why ? why : "unknown error"));
  }
  dlerror();
  const auto entry = reinterpret_cast<PluginEntryPoint>(dlsym(handle, KINCAL_PLUGIN_ENTRY_POINT));
  if (!entry) {
    throw std::invalid_argument("plugin " + path +
                                ": no entry point " KINCAL_PLUGIN_ENTRY_POINT
                                " (define one with KINCAL_PLUGIN from framework/plugin.h)");
  }
  const char* version = entry(nullptr);
  const std::string built = version ? version : "(none)";
  if (built != KINCAL_VERSION_STRING) {
    throw std::invalid_argument("plugin " + path + ": built against kincal " + OneLine(built) + ", this is kincal " +
                                KINCAL_VERSION_STRING + "; rebuild it against this version");
  }
  try {
    entry(&registrar);
  } catch (const std::exception& e) {
    throw std::invalid_argument("plugin " + path + ": " + OneLine(e.what()));
  }
  loaded.insert({&registrar, canonical});
  // Never dlclose(handle): the registered factories and everything they build point into the library.
}

std::vector<std::string> PluginPathsFromEnvironment() {
  std::vector<std::string> paths;
  const char* env = std::getenv("KINCAL_PLUGIN_PATH");
  if (!env) return paths;
  const std::string text = env;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t colon = text.find(':', start);
    const std::string entry = text.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    if (!entry.empty()) paths.push_back(entry);
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  return paths;
}

}  // namespace kincal
