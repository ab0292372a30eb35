#pragma once
// Registry by name (Drake's MakeSolver / solver available(), Ceres' factories): every estimator and
// compensator is created from its name and an options map (YAML), so the command line and studies only
// wire registered pieces together. A backend whose library is missing stays listed, with the reason.
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

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
    bool available = true;
    std::string why_unavailable;
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
  bool IsAvailable(const std::string& name) const {
    const auto it = entries_.find(name);
    return it != entries_.end() && it->second.available;
  }
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
    const Entry& entry = Get(name);
    if (!entry.available) throw std::invalid_argument("method '" + name + "' is not available: " + entry.why_unavailable);
    return entry.factory(options);
  }

 private:
  std::map<std::string, Entry> entries_;
};

// Helpers for Options structs read from YAML: unknown keys are errors naming the key and its place.
class OptionsReader {
 public:
  OptionsReader(const YAML::Node& node, std::string what);
  // Each getter leaves *value unchanged when the key is absent.
  void Get(const std::string& key, double* value);
  void Get(const std::string& key, int* value);
  void Get(const std::string& key, bool* value);
  void Get(const std::string& key, std::string* value);
  void Get(const std::string& key, std::vector<std::string>* value);
  // A length with an optional unit ("10um", "0.01mm"; plain numbers are metres).
  void GetLength(const std::string& key, double* value);
  // An angle in degrees in the file, radians in *value.
  void GetAngleDeg(const std::string& key, double* value);
  const YAML::Node& node() const { return node_; }
  // For keys a caller parses itself from node() (maps): marks `key` read for Finish().
  void MarkRead(const std::string& key) { read_.push_back(key); }
  // Throws for any key not read by a Get call. Call last.
  void Finish() const;
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const;

 private:
  YAML::Node node_;
  std::string what_;
  std::vector<std::string> read_;
};

}  // namespace kincal
