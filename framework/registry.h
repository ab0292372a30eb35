#pragma once
// Registry by name (Drake's MakeSolver, Ceres' factories): every estimator and compensator is created
// from its name and an options map (YAML), so the command line and studies only wire registered pieces
// together. Every backend is required at build time (CMakeLists.txt), so every registered method can be
// created. Each entry carries its options' documentation (framework/options.h).
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "framework/options.h"

namespace kincal {

template <typename Product>
class Registry {
 public:
  // Builds a product from options; throws std::invalid_argument for unknown keys or invalid values.
  using Factory = std::function<std::unique_ptr<Product>(const YAML::Node& options)>;
  struct Entry {
    std::string name;
    std::string description;  // one line, shown by `kincal methods`
    Factory factory;
    std::vector<OptionDoc> options;  // key, type, default and doc of each option (`kincal methods`)
  };

  void Register(Entry entry) {
    const std::string name = entry.name;
    entries_[name] = std::move(entry);
  }
  std::vector<std::string> RegisteredNames() const {
    std::vector<std::string> names;
    for (const auto& kv : entries_) names.push_back(kv.first);
    return names;
  }
  bool IsRegistered(const std::string& name) const { return entries_.count(name) > 0; }
  const Entry& Get(const std::string& name) const {
    const auto it = entries_.find(name);
    if (it == entries_.end()) {
      std::string list;
      for (const auto& kv : entries_) list += (list.empty() ? "" : ", ") + kv.first;
      throw std::invalid_argument("unknown method '" + name + "' (registered: " + list + ")");
    }
    return it->second;
  }
  std::unique_ptr<Product> Create(const std::string& name, const YAML::Node& options = YAML::Node()) const {
    return Get(name).factory(options);
  }

 private:
  std::map<std::string, Entry> entries_;
};

}  // namespace kincal
