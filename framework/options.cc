#include "framework/options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

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
  if (!mark.is_null())
    where = "line " + std::to_string(mark.line + 1) + ", column " + std::to_string(mark.column + 1) + ": " + where;
  throw OptionsError(OneLine(where + ": '" + key + "': " + what), key, mark.is_null() ? 0 : mark.line + 1,
                     mark.is_null() ? 0 : mark.column + 1, what);
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
  if (s == "true" || s == "yes" || s == "on")
    *value = true;
  else if (s == "false" || s == "no" || s == "off")
    *value = false;
  else
    Fail(key, "expected true or false");
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

void OptionsReader::Get(const std::string& key, std::vector<double>* value) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  const YAML::Node n = node_[key];
  if (!n.IsScalar() && !n.IsSequence()) Fail(key, "expected a list of numbers");
  std::vector<double> values;
  const auto add = [&](const YAML::Node& item) {
    double v = 0.0;
    if (!item.IsScalar() || !ParseDouble(item.Scalar(), &v)) {
      Fail(key, "expected a list of numbers, got " + options_detail::Quoted(item));
    }
    values.push_back(v);
  };
  if (n.IsScalar()) {
    add(n);
  } else {
    for (const auto& item : n) add(item);
  }
  *value = std::move(values);
}

bool OptionsReader::Has(const std::string& key) const { return node_ && node_.IsMap() && node_[key]; }

void OptionsReader::GetLength(const std::string& key, double* value, const std::string& plain_unit) {
  read_.push_back(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return;
  if (!node_[key].IsScalar()) Fail(key, "expected a length such as 10um or 0.01mm");
  try {
    *value = ParseLength(node_[key].Scalar(), LengthUnit(plain_unit));
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

namespace {

std::string Number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

Requirement<double> Positive() {
  return [](const double& v) { return v > 0.0 && std::isfinite(v) ? "" : "must be positive"; };
}

Requirement<double> NonNegative() {
  return [](const double& v) { return v >= 0.0 && std::isfinite(v) ? "" : "must be finite and >= 0"; };
}

Requirement<double> Between(double lo, double hi, bool lo_open, bool hi_open) {
  const std::string text =
      std::string("must lie in ") + (lo_open ? "(" : "[") + Number(lo) + ", " + Number(hi) + (hi_open ? ")" : "]");
  return [=](const double& v) {
    const bool above = lo_open ? v > lo : v >= lo;
    const bool below = hi_open ? v < hi : v <= hi;
    return above && below && std::isfinite(v) ? std::string() : text;
  };
}

Requirement<int> AtLeast(int lo) {
  return [lo](const int& v) { return v >= lo ? std::string() : "must be >= " + std::to_string(lo); };
}

Requirement<int> Within(int lo, int hi) {
  return [lo, hi](const int& v) {
    return v >= lo && v <= hi ? std::string() : "must be in " + std::to_string(lo) + ".." + std::to_string(hi);
  };
}

Requirement<std::string> OneOf(std::vector<std::string> choices) {
  std::string text = "must be ";
  for (size_t i = 0; i < choices.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  }
  return [choices, text](const std::string& v) {
    return std::find(choices.begin(), choices.end(), v) != choices.end() ? std::string() : text;
  };
}

Requirement<std::vector<double>> EachNonNegative() {
  return [](const std::vector<double>& values) {
    for (double v : values) {
      if (!(v >= 0.0) || !std::isfinite(v)) return std::string("must be finite and >= 0 each");
    }
    return std::string();
  };
}

namespace options_detail {

std::string Show(double v) { return Number(v); }
std::string Show(int v) { return std::to_string(v); }
std::string Show(bool v) { return v ? "true" : "false"; }
std::string Show(const std::string& v) { return "'" + OneLine(v) + "'"; }
std::string Show(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + OneLine(x);
  return "[" + s + "]";
}
std::string Show(const std::vector<double>& v) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : ", ") + Number(x);
  return "[" + s + "]";
}

std::string TypeName(double, OptionUnit unit) {
  if (unit == OptionUnit::kLengthMm) return "length (mm)";
  return unit == OptionUnit::kLength ? "length" : unit == OptionUnit::kAngleDeg ? "angle (deg)" : "number";
}
std::string TypeName(int, OptionUnit) { return "integer"; }
std::string TypeName(bool, OptionUnit) { return "true/false"; }
std::string TypeName(const std::string&, OptionUnit) { return "text"; }
std::string TypeName(const std::vector<std::string>&, OptionUnit) { return "list"; }
std::string TypeName(const std::vector<double>&, OptionUnit) { return "list of numbers"; }

void ReadValue(OptionsReader* reader, const std::string& key, OptionUnit unit, double* value) {
  if (unit == OptionUnit::kLength || unit == OptionUnit::kLengthMm) {
    reader->GetLength(key, value, unit == OptionUnit::kLength ? "m" : "mm");
  } else if (unit == OptionUnit::kAngleDeg) {
    reader->GetAngleDeg(key, value);
  } else {
    reader->Get(key, value);
  }
}

std::string Quoted(const YAML::Node& node) {
  if (node && node.IsScalar()) return "'" + OneLine(node.Scalar()) + "'";
  std::ostringstream s;
  s << node;
  return "'" + OneLine(s.str()) + "'";
}

}  // namespace options_detail

}  // namespace kincal
