#pragma once
// The study file parser's shared pieces (internal to studies/study_file*.cc): the Reader, which names every
// error by the key's path in the file ("datasets[2].simulate.noise") with its line and column, and
// ReadOptions, which reads a section declared by an OptionTable (studies/study_options.h) the same way.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "framework/error.h"
#include "framework/options.h"
#include "framework/units.h"
#include "studies/study.h"

namespace kincal::study_file {

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void Fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
    const YAML::Mark mark = at ? at.Mark() : YAML::Mark::null_mark();
    const int line = mark.is_null() ? 0 : mark.line + 1;
    const int column = mark.is_null() ? 0 : mark.column + 1;
    ThrowInputError(file_, line, column, key + ": " + what);
  }

  void ExpectMap(const YAML::Node& node, const std::string& key) const {
    if (!node.IsMap()) Fail(node, key, "expected a map");
  }
  void ExpectSequence(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence()) Fail(node, key, "expected a list");
  }

  // Fails on the first key of `node` not in `allowed`.
  void CheckKeys(const YAML::Node& node, const std::string& key, const std::vector<std::string>& allowed) const {
    ExpectMap(node, key);
    for (const auto& kv : node) {
      const std::string k = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Fail(kv.first, Join(key, k), "unknown key (expected one of: " + list + ")");
      }
    }
  }

  static std::string Join(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
  }

  std::string String(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) Fail(node, key, "expected a string");
    return node.Scalar();
  }
  double Number(const YAML::Node& node, const std::string& key) const {
    double v = 0.0;
    if (!node.IsScalar() || !ParseDouble(node.Scalar(), &v)) Fail(node, key, "expected a number");
    return v;
  }
  int Integer(const YAML::Node& node, const std::string& key, int min) const {
    const double v = Number(node, key);
    if (v != std::floor(v) || v < min || v > 1e9) {
      Fail(node, key, "expected an integer >= " + std::to_string(min) + ", got '" + node.Scalar() + "'");
    }
    return static_cast<int>(v);
  }
  bool Bool(const YAML::Node& node, const std::string& key) const {
    const std::string s = node.IsScalar() ? node.Scalar() : "";
    if (s == "true" || s == "yes" || s == "on") return true;
    if (s == "false" || s == "no" || s == "off") return false;
    Fail(node, key, "expected true or false");
  }
  // A length: mm unless the text carries a unit.
  double Length(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) Fail(node, key, "expected a length such as 10um or 0.01mm");
    double v = 0.0;
    try {
      v = ParseLength(node.Scalar(), LengthUnit("mm"));
    } catch (const std::invalid_argument& e) {
      Fail(node, key, e.what());
    }
    if (v < 0.0) Fail(node, key, "expected a length >= 0");
    return v;
  }
  std::vector<double> Numbers(const YAML::Node& node, const std::string& key) const {
    ExpectSequence(node, key);
    std::vector<double> out;
    for (size_t i = 0; i < node.size(); ++i) out.push_back(Number(node[i], key + "[" + std::to_string(i) + "]"));
    return out;
  }
  // A list of `n` angles in degrees, in rad.
  Eigen::VectorXd Angles(const YAML::Node& node, const std::string& key, int n) const {
    const std::vector<double> deg = Numbers(node, key);
    if (static_cast<int>(deg.size()) != n) {
      Fail(node, key, "expected " + std::to_string(n) + " angles (deg), got " + std::to_string(deg.size()));
    }
    Eigen::VectorXd out(n);
    for (int i = 0; i < n; ++i) out[i] = deg[i] * M_PI / 180.0;
    return out;
  }
  std::string Name(const YAML::Node& node, const std::string& key) const {
    const std::string s = String(node, key);
    if (s.empty()) Fail(node, key, "expected a non-empty name");
    for (char c : s) {
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '+')) {
        Fail(node, key, "names may hold letters, digits, '_', '-', '.' and '+' only, got '" + s + "'");
      }
    }
    return s;
  }

 private:
  std::string file_;
};

// Present and not null (a default-constructed YAML::Node is a defined null).
inline bool Given(const YAML::Node& node) { return node && !node.IsNull(); }

// `path` relative to the study file's folder (absolute paths as they are).
std::string Resolve(const std::string& study_path, const std::string& path);

// The section at `node` (a map, or absent or null for the defaults) read by `table`: an unknown key fails at
// the key, a wrong type or a value out of range at the value, each named by its path under `key`.
template <typename O>
O ReadOptions(const Reader& r, const OptionTable<O>& table, const YAML::Node& node, const std::string& key) {
  if (!Given(node)) return table.Read(YAML::Node());
  std::vector<std::string> keys;
  for (const OptionDoc& d : table.Docs()) keys.push_back(d.key);
  r.CheckKeys(node, key, keys);
  try {
    return table.Read(node);
  } catch (const OptionsError& e) {
    ThrowInputError(r.file(), e.line(), e.column(), Reader::Join(key, e.key()) + ": " + e.reason());
  }
}

// The sections, one file each: study_file_datasets.cc, study_file_methods.cc, study_file_validation.cc.
DatasetSpec ReadDatasetSpec(const Reader& r, const YAML::Node& node, const std::string& key, int dof);
PipelineSpec ReadPipeline(const Reader& r, const YAML::Node& node, const std::string& key,
                          const EstimatorRegistry& registry);
CompensatorSpec ReadCompensator(const Reader& r, const YAML::Node& node, const std::string& key,
                                const CompensatorRegistry& registry);
ValidationSpec ReadValidation(const Reader& r, const YAML::Node& node, const std::string& key, const Robot& nominal);

}  // namespace kincal::study_file
