#include "framework/registry.h"

#include <algorithm>
#include <cmath>

#include "framework/error.h"
#include "framework/units.h"

namespace kincal {

OptionsReader::OptionsReader(const YAML::Node& node, std::string what) : node_(node), what_(std::move(what)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) ThrowInputError("options of " + what_ + ": expected a map");
}

void OptionsReader::Fail(const std::string& key, const std::string& what) const {
  const YAML::Node n = node_ && node_.IsMap() ? node_[key] : YAML::Node();
  const YAML::Mark mark = n ? n.Mark() : YAML::Mark::null_mark();
  std::string where = "options of " + what_;
  if (!mark.is_null()) where = "line " + std::to_string(mark.line + 1) + ", column " + std::to_string(mark.column + 1) + ": " + where;
  ThrowInputError(where + ": '" + key + "': " + what);
}

void OptionsReader::Get(const std::string& key, double* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  const YAML::Node n = node_[key];
  if (!n.IsScalar() || !ParseDouble(n.Scalar(), value)) Fail(key, "expected a number");
}

void OptionsReader::Get(const std::string& key, int* value) {
  double v = *value;
  Get(key, &v);
  if (v != std::floor(v)) Fail(key, "expected an integer");
  // Converting a double beyond int's range is undefined behaviour, not an error: check first.
  if (std::fabs(v) > 2147483647.0) Fail(key, "expected an integer of at most 2147483647 in magnitude");
  *value = static_cast<int>(v);
}

void OptionsReader::Get(const std::string& key, bool* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  const std::string s = node_[key].Scalar();
  if (s == "true" || s == "yes" || s == "on") *value = true;
  else if (s == "false" || s == "no" || s == "off") *value = false;
  else Fail(key, "expected true or false");
}

void OptionsReader::Get(const std::string& key, std::string* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  if (!node_[key].IsScalar()) Fail(key, "expected a string");
  *value = node_[key].Scalar();
}

void OptionsReader::Get(const std::string& key, std::vector<std::string>* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  const YAML::Node n = node_[key];
  value->clear();
  if (n.IsScalar()) {
    value->push_back(n.Scalar());
    return;
  }
  if (!n.IsSequence()) Fail(key, "expected a list of strings");
  for (const auto& item : n) {
    if (!item.IsScalar()) Fail(key, "expected a list of strings");
    value->push_back(item.Scalar());
  }
}

void OptionsReader::GetLength(const std::string& key, double* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  try {
    *value = ParseLength(node_[key].Scalar(), LengthUnit("m"));
  } catch (const std::invalid_argument& e) {
    Fail(key, e.what());
  }
}

void OptionsReader::GetAngleDeg(const std::string& key, double* value) {
  if (!node_ || !node_.IsMap() || !node_[key]) {
    read_.push_back(key);
    return;
  }
  double deg = 0.0;
  Get(key, &deg);
  *value = deg * M_PI / 180.0;
}

void OptionsReader::Finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    if (std::find(read_.begin(), read_.end(), key) == read_.end()) {
      std::string list;
      for (const auto& r : read_) list += (list.empty() ? "" : ", ") + r;
      Fail(key, "unknown option (expected one of: " + list + ")");
    }
  }
}

}  // namespace kincal
