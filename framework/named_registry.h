#pragma once
// A table of entries by name, for extension points whose entries are not built from an options map
// (model conventions, program formats): each entry is a struct with a `name` field and whatever the
// extension needs (a factory, a conversion, file extensions). Registry<Product> (framework/registry.h)
// is the same idea for estimators and compensators, whose factories all take YAML options.
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kincal {

template <typename EntryType>
class NamedRegistry {
 public:
  using Entry = EntryType;
  // `kind` names an entry in messages: "unknown convention 'craig' (registered: dh, hayati, ...)".
  explicit NamedRegistry(std::string kind) : kind_(std::move(kind)) {}

  // Throws std::invalid_argument for an empty name or one already taken.
  void Register(Entry entry) {
    if (entry.name.empty()) throw std::invalid_argument("a " + kind_ + " needs a name");
    if (entries_.count(entry.name)) throw std::invalid_argument(kind_ + " name '" + entry.name + "' is taken");
    const std::string name = entry.name;
    entries_.emplace(name, std::move(entry));
  }
  // Removes an entry (tests and examples that register one for a while); false when there was none.
  bool Unregister(const std::string& name) { return entries_.erase(name) > 0; }
  // In alphabetical order.
  std::vector<std::string> RegisteredNames() const {
    std::vector<std::string> names;
    for (const auto& kv : entries_) names.push_back(kv.first);
    return names;
  }
  std::vector<const Entry*> Entries() const {
    std::vector<const Entry*> out;
    for (const auto& kv : entries_) out.push_back(&kv.second);
    return out;
  }
  bool IsRegistered(const std::string& name) const { return entries_.count(name) > 0; }
  // Throws std::invalid_argument naming the registered entries for an unknown name.
  const Entry& Get(const std::string& name) const {
    const auto it = entries_.find(name);
    if (it == entries_.end()) throw std::invalid_argument("unknown " + kind_ + " '" + name + "' (expected one of: " + NameList() + ")");
    return it->second;
  }
  std::string NameList() const {
    std::string list;
    for (const auto& kv : entries_) list += (list.empty() ? "" : ", ") + kv.first;
    return list;
  }

 private:
  std::string kind_;
  std::map<std::string, Entry> entries_;
};

}  // namespace kincal
