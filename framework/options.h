#pragma once
// Options declared once. Every Options struct of an estimator or compensator has one OptionTable: a
// list of {key, member (or getter and setter), unit, doc, requirement}, the model Drake's
// nlopt_solver.cc KnownOptions gives. From it are derived
//   - reading from YAML (Read): a wrong type, an unknown key and a value out of its range all fail with
//     the line and column of the value (yaml-cpp's Node::Mark), through OptionsReader::Fail;
//   - validation (Validate, behind each struct's IsValid): the same requirements on values set in code;
//   - the documentation (Docs, printed by `kincal methods --options NAME`): key, type, default, doc.
// Adding an option is one line of its struct's table:
//   .Add("max_iterations", &O::max_iterations, "passes over the data that propose a step", AtLeast(0))
// Tables compose: Include(inner table, &O::member) reads a nested struct's keys at the same level, and
// Include(base table) a base struct's. Rule() adds a requirement between several keys.
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace kincal {

// The error OptionsReader::Fail throws: its message as described there, and its parts for a caller that
// names the place its own way (a study file: "file:line:column: datasets[0].simulate.noise: ...").
class OptionsError : public std::invalid_argument {
 public:
  OptionsError(const std::string& message, std::string key, int line, int column, std::string reason)
      : std::invalid_argument(message),
        key_(std::move(key)),
        line_(line),
        column_(column),
        reason_(std::move(reason)) {}
  const std::string& key() const { return key_; }
  int line() const { return line_; }      // 1-based; 0 when unknown
  int column() const { return column_; }  // 1-based; 0 when unknown
  const std::string& reason() const { return reason_; }

 private:
  std::string key_;
  int line_, column_;
  std::string reason_;
};

// Reads the keys of an options map: unknown keys are errors naming the key and its place.
class OptionsReader {
 public:
  OptionsReader(const YAML::Node& node, std::string what);
  // Each getter leaves *value unchanged when the key is absent.
  void Get(const std::string& key, double* value);
  void Get(const std::string& key, int* value);
  void Get(const std::string& key, bool* value);
  void Get(const std::string& key, std::string* value);
  void Get(const std::string& key, std::vector<std::string>* value);
  void Get(const std::string& key, std::vector<double>* value);
  // A length with an optional unit ("10um", "0.01mm"; plain numbers are in `plain_unit`, metres by default).
  void GetLength(const std::string& key, double* value, const std::string& plain_unit = "m");
  // An angle in degrees in the file, radians in *value.
  void GetAngleDeg(const std::string& key, double* value);
  bool Has(const std::string& key) const;
  const YAML::Node& node() const { return node_; }
  // For keys a caller parses itself from node() (maps): marks `key` read for Finish().
  void MarkRead(const std::string& key) { read_.push_back(key); }
  // Throws for any key not read by a Get call. Call last.
  void Finish() const;
  // Throws OptionsError "line L, column C: options of <what>: '<key>': <what>" (the value's place).
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const;

 private:
  YAML::Node node_;
  std::string what_;
  std::vector<std::string> read_;
};

// How an option reads and shows: a plain value, a length (m, units allowed in files), an angle (rad
// inside, degrees in files) or a length whose plain numbers in files are millimetres (study files).
enum class OptionUnit { kPlain, kLength, kAngleDeg, kLengthMm };

// A requirement on a value: "" when it holds, else what it must be ("must be positive").
template <typename T>
using Requirement = std::function<std::string(const T&)>;

Requirement<double> Positive();                                                 // finite and > 0
Requirement<double> NonNegative();                                              // finite and >= 0
Requirement<double> Between(double lo, double hi, bool lo_open, bool hi_open);  // finite, in the interval
Requirement<int> AtLeast(int lo);
Requirement<int> Within(int lo, int hi);  // lo..hi
Requirement<std::string> OneOf(std::vector<std::string> choices);
Requirement<std::vector<double>> EachNonNegative();  // every entry finite and >= 0

// One line of `kincal methods --options NAME`.
struct OptionDoc {
  std::string key;
  std::string type;           // "number", "integer", "true/false", "text", "list", "length", "angle (deg)"
  std::string default_value;  // as a file would write it
  std::string doc;
};

namespace options_detail {
std::string Show(double v);
std::string Show(int v);
std::string Show(bool v);
std::string Show(const std::string& v);
std::string Show(const std::vector<std::string>& v);
std::string Show(const std::vector<double>& v);
std::string TypeName(double, OptionUnit unit);
std::string TypeName(int, OptionUnit);
std::string TypeName(bool, OptionUnit);
std::string TypeName(const std::string&, OptionUnit);
std::string TypeName(const std::vector<std::string>&, OptionUnit);
std::string TypeName(const std::vector<double>&, OptionUnit);
void ReadValue(OptionsReader* reader, const std::string& key, OptionUnit unit, double* value);
template <typename T>
void ReadValue(OptionsReader* reader, const std::string& key, OptionUnit, T* value) {
  reader->Get(key, value);
}
std::string Quoted(const YAML::Node& node);
}  // namespace options_detail

template <typename O>
class OptionTable {
 public:
  struct Field {
    OptionDoc doc;
    std::function<void(OptionsReader*, O*)> read;  // reads the key when present, checks it
    std::function<std::string(const O&)> check;    // "" or "<key> must be ..., got ..."
    std::function<std::string(const O&)> show;     // the value as a file writes it
  };

  // `what` names the options in messages ("least_squares").
  explicit OptionTable(std::string what) : what_(std::move(what)) {}

  // A member read as is (numbers, integers, true/false, text, lists).
  template <typename T>
  OptionTable& Add(const std::string& key, T O::*member, const std::string& doc, Requirement<T> require = nullptr) {
    return Add<T>(key, OptionUnit::kPlain, member, doc, std::move(require));
  }
  // A length or an angle member (OptionUnit).
  template <typename T>
  OptionTable& Add(const std::string& key, OptionUnit unit, T O::*member, const std::string& doc,
                   Requirement<T> require = nullptr) {
    return AddAccess<T>(
        key, unit, [member](O* o) { return &(o->*member); }, doc, std::move(require));
  }
  // A value reached through get and set (an enumeration read by name: set throws std::invalid_argument
  // for a bad name, and the message is the option's error).
  template <typename T>
  OptionTable& Add(const std::string& key, std::function<T(const O&)> get, std::function<void(O*, const T&)> set,
                   const std::string& doc) {
    Field f;
    f.doc = {key, options_detail::TypeName(T(), OptionUnit::kPlain), "", doc};
    f.read = [key, get, set](OptionsReader* reader, O* o) {
      T value = get(*o);
      reader->Get(key, &value);
      if (!reader->Has(key)) return;
      try {
        set(o, value);
      } catch (const std::invalid_argument& e) {
        reader->Fail(key, e.what());
      }
    };
    f.check = [](const O&) { return std::string(); };
    f.show = [get](const O& o) { return options_detail::Show(get(o)); };
    return Push(std::move(f));
  }
  // The keys of a nested struct, at this level.
  template <typename S>
  OptionTable& Include(const OptionTable<S>& inner, S O::*member) {
    for (const auto& g : inner.fields()) {
      Field f;
      f.doc = g.doc;
      f.read = [g, member](OptionsReader* reader, O* o) { g.read(reader, &(o->*member)); };
      f.check = [g, member](const O& o) { return g.check(o.*member); };
      f.show = [g, member](const O& o) { return g.show(o.*member); };
      fields_.push_back(std::move(f));
    }
    for (const auto& r : inner.rules()) {
      rules_.push_back({r.keys, [r, member](const O& o) { return r.check(o.*member); }});
    }
    return *this;
  }
  // The keys of a base struct B of O.
  template <typename B>
  OptionTable& Include(const OptionTable<B>& base) {
    static_assert(std::is_base_of<B, O>::value, "Include(table): B must be a base of O");
    for (const auto& g : base.fields()) {
      Field f;
      f.doc = g.doc;
      f.read = [g](OptionsReader* reader, O* o) { g.read(reader, static_cast<B*>(o)); };
      f.check = [g](const O& o) { return g.check(static_cast<const B&>(o)); };
      f.show = [g](const O& o) { return g.show(static_cast<const B&>(o)); };
      fields_.push_back(std::move(f));
    }
    for (const auto& r : base.rules()) {
      rules_.push_back({r.keys, [r](const O& o) { return r.check(static_cast<const B&>(o)); }});
    }
    return *this;
  }
  // Keys a struct parses itself (a key that takes several forms, e.g. on, off or a map): `read` reads
  // them through the reader (its Get calls, or MarkRead); `doc` documents the first of them.
  OptionTable& AddRead(OptionDoc doc, std::function<void(OptionsReader*, O*)> read) {
    Field f;
    f.doc = doc;
    f.read = std::move(read);
    f.check = [](const O&) { return std::string(); };
    const std::string shown = doc.default_value;
    f.show = [shown](const O&) { return shown; };
    return Push(std::move(f));
  }
  // Documents a key that another field's read() reads (its doc only).
  OptionTable& Document(OptionDoc doc) {
    return AddRead(std::move(doc), [](OptionsReader*, O*) {});
  }
  // A requirement between keys: check returns "" or the message; a file breaking it fails at the first
  // of `keys` it gives.
  struct RuleEntry {
    std::vector<std::string> keys;
    std::function<std::string(const O&)> check;
  };
  OptionTable& Rule(std::vector<std::string> keys, std::function<std::string(const O&)> check) {
    rules_.push_back({std::move(keys), std::move(check)});
    return *this;
  }

  // Defaults, then the keys of `node`; throws std::invalid_argument (with line and column) for an
  // unknown key, a wrong type or a value that breaks its requirement.
  O Read(const YAML::Node& node) const {
    O o;
    OptionsReader reader(node, what_);
    for (const auto& f : fields_) f.read(&reader, &o);
    for (const auto& r : rules_) {
      const std::string why = r.check(o);
      if (why.empty()) continue;
      for (const auto& key : r.keys) {
        if (reader.Has(key)) reader.Fail(key, why);
      }
    }
    reader.Finish();
    return o;
  }
  // Every requirement on `o`; the first broken one into *why.
  bool Validate(const O& o, std::string* why) const {
    for (const auto& f : fields_) {
      std::string message = f.check(o);
      if (message.empty()) continue;
      if (why) *why = std::move(message);
      return false;
    }
    for (const auto& r : rules_) {
      std::string message = r.check(o);
      if (message.empty()) continue;
      if (why) *why = std::move(message);
      return false;
    }
    return true;
  }
  // Key, type, default (of a default-constructed O) and doc of every option, in declaration order.
  std::vector<OptionDoc> Docs() const {
    const O defaults{};
    std::vector<OptionDoc> docs;
    for (const auto& f : fields_) {
      OptionDoc d = f.doc;
      d.default_value = f.show(defaults);
      docs.push_back(std::move(d));
    }
    return docs;
  }

  const std::vector<Field>& fields() const { return fields_; }
  const std::vector<RuleEntry>& rules() const { return rules_; }

 private:
  template <typename T>
  OptionTable& AddAccess(const std::string& key, OptionUnit unit, std::function<T*(O*)> access, const std::string& doc,
                         Requirement<T> require) {
    Field f;
    f.doc = {key, options_detail::TypeName(T(), unit), "", doc};
    f.read = [key, unit, access, require](OptionsReader* reader, O* o) {
      T* value = access(o);
      options_detail::ReadValue(reader, key, unit, value);
      if (!require || !reader->Has(key)) return;
      const std::string why = require(InFileUnits(*value, unit));
      if (!why.empty()) reader->Fail(key, why + ", got " + options_detail::Quoted(reader->node()[key]));
    };
    f.check = [key, unit, access, require](const O& o) {
      if (!require) return std::string();
      const T& value = *access(const_cast<O*>(&o));
      const std::string why = require(InFileUnits(value, unit));
      if (why.empty()) return why;
      return key + " " + why + ", got " + ShowIn(value, unit);
    };
    f.show = [access, unit](const O& o) { return ShowIn(*access(const_cast<O*>(&o)), unit); };
    return Push(std::move(f));
  }
  // Requirements are stated in the file's units: degrees for angles.
  template <typename T>
  static const T& InFileUnits(const T& value, OptionUnit) {
    return value;
  }
  static double InFileUnits(const double& value, OptionUnit unit) {
    return unit == OptionUnit::kAngleDeg ? value * 180.0 / 3.14159265358979323846 : value;
  }
  template <typename T>
  static std::string ShowIn(const T& value, OptionUnit) {
    return options_detail::Show(value);
  }
  static std::string ShowIn(const double& value, OptionUnit unit) {
    if (unit == OptionUnit::kAngleDeg) return options_detail::Show(InFileUnits(value, unit));
    if (unit == OptionUnit::kLengthMm) return options_detail::Show(value * 1e3) + " mm";
    return options_detail::Show(value) + (unit == OptionUnit::kLength ? " m" : "");
  }
  OptionTable& Push(Field f) {
    fields_.push_back(std::move(f));
    return *this;
  }

  std::string what_;
  std::vector<Field> fields_;
  std::vector<RuleEntry> rules_;
};

}  // namespace kincal
