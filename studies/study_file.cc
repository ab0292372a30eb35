// Study file parser (the schema is documented in study.h and examples/studies/). Every error names the
// key by its path in the file ("datasets[2].simulate.noise") with the line and column. Over 600 lines on
// purpose: one reader per section of one schema, sharing the Reader and its key paths.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include <yaml-cpp/yaml.h>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "robot/robot_file.h"
#include "studies/study.h"
#include "framework/units.h"

namespace kincal {
namespace {

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
bool Given(const YAML::Node& node) { return node && !node.IsNull(); }

std::string Resolve(const std::string& study_path, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(study_path).parent_path() / p).lexically_normal().string();
}

std::string OptionsText(const YAML::Node& node) {
  if (!node || node.IsNull()) return "";
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node;
  return out.c_str();
}

RobotSpec ReadRobot(const Reader& r, const YAML::Node& node, const std::string& key, const std::string& study_path) {
  RobotSpec spec;
  try {
    if (node.IsScalar()) {
      spec.source = node.Scalar();
      spec.robot = ReadRobotFile(Resolve(study_path, node.Scalar()));
    } else if (node.IsMap()) {
      spec.source = "inline";
      YAML::Emitter out;
      out << node;
      spec.robot = ParseRobotYaml(out.c_str(), key);
    } else {
      r.Fail(node, key, "expected a robot file path or an inline robot map");
    }
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).rfind(r.file(), 0) == 0) throw;
    r.Fail(node, key, e.what());
  }
  return spec;
}

void ReadSimulator(const Reader& r, const YAML::Node& node, const std::string& key, int dof, DatasetSpec* d) {
  r.CheckKeys(node, key,
              {"protocol", "poses", "stops", "step", "start", "order", "noise", "noise_range", "orientation",
               "orientation_noise", "marker"});
  SimulatorOptions& o = d->simulator;
  const auto k = [&](const char* name) { return Reader::Join(key, name); };
  if (node["protocol"]) o.protocol = r.String(node["protocol"], k("protocol"));
  if (o.protocol != "sweep" && o.protocol != "random") {
    r.Fail(node["protocol"], k("protocol"), "expected sweep or random, got '" + o.protocol + "'");
  }
  if (node["poses"]) o.poses = r.Integer(node["poses"], k("poses"), 1);
  if (node["stops"]) o.stops = r.Integer(node["stops"], k("stops"), 2);
  if (node["step"]) o.step = r.Number(node["step"], k("step")) * M_PI / 180.0;
  if (node["start"]) o.start = r.Angles(node["start"], k("start"), dof);
  if (node["order"]) {
    for (double j : r.Numbers(node["order"], k("order"))) {
      if (j != std::floor(j) || j < 1 || j > dof) {
        r.Fail(node["order"], k("order"), "expected joint numbers 1.." + std::to_string(dof));
      }
      o.sweep_order.push_back(static_cast<int>(j));
    }
  }
  if (node["noise"]) o.noise_sigma = r.Length(node["noise"], k("noise"));
  if (node["noise_range"]) o.noise_range_coefficient = r.Length(node["noise_range"], k("noise_range"));
  if (node["orientation"]) o.orientation = r.Bool(node["orientation"], k("orientation"));
  if (node["orientation_noise"]) {
    o.orientation_noise = r.Number(node["orientation_noise"], k("orientation_noise")) * M_PI / 180.0;
    if (o.orientation_noise < 0) r.Fail(node["orientation_noise"], k("orientation_noise"), "expected >= 0");
  }
  if (node["marker"]) {
    const std::vector<double> xyz = r.Numbers(node["marker"], k("marker"));
    if (xyz.size() != 3) r.Fail(node["marker"], k("marker"), "expected [x, y, z] in mm");
    d->marker = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * 1e-3;
  }
  std::string why;
  if (!o.IsValid(&why)) r.Fail(node, key, why);
  char text[256];
  if (o.protocol == "sweep") {
    std::snprintf(text, sizeof(text), "simulated, sweep protocol: %d stops %.4g deg apart per joint", o.stops,
                  o.step * 180.0 / M_PI);
  } else {
    std::snprintf(text, sizeof(text), "simulated, random protocol: %d poses", o.poses);
  }
  d->summary = text;
  std::snprintf(text, sizeof(text), ", noise %.4g um + %.4g um/m per axis", o.noise_sigma * 1e6,
                o.noise_range_coefficient * 1e6);
  d->summary += text;
  if (o.orientation) d->summary += ", with orientation";
  if (d->marker) {
    std::snprintf(text, sizeof(text), ", marker at [%.4g, %.4g, %.4g] mm", (*d->marker)[0] * 1e3, (*d->marker)[1] * 1e3,
                  (*d->marker)[2] * 1e3);
    d->summary += text;
  }
}

void ReadVary(const Reader& r, const YAML::Node& node, const std::string& key, DatasetSpec* d) {
  r.ExpectMap(node, key);
  if (node.size() != 1) r.Fail(node, key, "expected exactly one knob, e.g. {noise: [1um, 10um]}");
  const auto kv = *node.begin();
  KnobSweep s;
  s.knob = kv.first.Scalar();
  const std::string k = Reader::Join(key, s.knob);
  static const std::vector<std::string> knobs = {"noise", "noise_range", "poses", "stops", "step", "arc"};
  if (std::find(knobs.begin(), knobs.end(), s.knob) == knobs.end()) {
    r.Fail(kv.first, k, "unknown knob (expected one of: noise, noise_range, poses, stops, step, arc)");
  }
  r.ExpectSequence(kv.second, k);
  if (kv.second.size() == 0) r.Fail(kv.second, k, "expected at least one value");
  for (size_t i = 0; i < kv.second.size(); ++i) {
    const YAML::Node v = kv.second[i];
    const std::string ki = k + "[" + std::to_string(i) + "]";
    if (s.knob == "noise" || s.knob == "noise_range")
      s.values.push_back(r.Length(v, ki));
    else if (s.knob == "poses")
      s.values.push_back(r.Integer(v, ki, 1));
    else if (s.knob == "stops")
      s.values.push_back(r.Integer(v, ki, 2));
    else
      s.values.push_back(r.Number(v, ki) * M_PI / 180.0);
    s.texts.push_back(v.Scalar());
  }
  const std::string& protocol = d->simulator.protocol;
  if ((s.knob == "stops" || s.knob == "step" || s.knob == "arc") && protocol != "sweep") {
    r.Fail(kv.first, k, "this knob needs the sweep protocol");
  }
  if (s.knob == "poses" && protocol != "random")
    r.Fail(kv.first, k, "this knob needs the random protocol (sweeps: stops)");
  d->vary = s;
}

// The split of a measured dataset (`split:`), after its source (`file:` or `tables:`).
void ReadSplit(const Reader& r, const YAML::Node& node, const std::string& key, DatasetSpec* d) {
  const std::string sk = key + ".split";
  if (!node["split"] || (node["split"].IsScalar() && node["split"].Scalar() == "column")) {
    if (d->tables)
      r.Fail(node["tables"], key + ".tables",
             "tables have no split column: give split: {every: N} or {test_fraction: F}");
    d->split = DatasetSpec::Split::kColumn;
    d->summary += ", test rows from its split column";
    return;
  }
  const YAML::Node s = node["split"];
  r.CheckKeys(s, sk, {"test_fraction", "every"});
  if (s.size() != 1) r.Fail(s, sk, "expected one of {test_fraction: F}, {every: N} or column");
  if (s["test_fraction"]) {
    d->split = DatasetSpec::Split::kFraction;
    d->test_fraction = r.Number(s["test_fraction"], sk + ".test_fraction");
    if (!(d->test_fraction > 0.0 && d->test_fraction < 1.0)) {
      r.Fail(s["test_fraction"], sk + ".test_fraction", "expected a fraction between 0 and 1");
    }
    d->summary += ", random test fraction " + s["test_fraction"].Scalar() + " per trial";
  } else {
    d->split = DatasetSpec::Split::kEvery;
    d->every = r.Integer(s["every"], sk + ".every", 2);
    d->summary += ", every " + std::to_string(d->every) + "th pose is a test pose";
  }
}

void CheckReadable(const Reader& r, const YAML::Node& node, const std::string& key, const std::string& path) {
  try {
    ReadFileToString(path);
  } catch (const std::invalid_argument&) {
    r.Fail(node, key, "cannot read '" + path + "'");
  }
}

// `tables:` {joints, positions: {marker: path}, sequence, units}: whitespace tables, row i of each is pose
// i; `sequence` (optional): the unfiltered joint readings the poses were filtered from (pose_tables.h).
void ReadTables(const Reader& r, const YAML::Node& node, const std::string& key, DatasetSpec* d) {
  r.CheckKeys(node, key, {"joints", "positions", "sequence", "units"});
  if (!node["joints"]) r.Fail(node, key, "missing key 'joints' (a table of joint readings, one column per joint)");
  if (!node["positions"]) r.Fail(node, key, "missing key 'positions' (marker: table of x y z)");
  d->tables = true;
  d->file_as_written = r.String(node["joints"], key + ".joints");
  d->file = Resolve(r.file(), d->file_as_written);
  CheckReadable(r, node["joints"], key + ".joints", d->file);
  const YAML::Node positions = node["positions"];
  r.ExpectMap(positions, key + ".positions");
  if (positions.size() == 0) r.Fail(positions, key + ".positions", "expected at least one marker");
  for (const auto& kv : positions) {
    const std::string pk = key + ".positions." + kv.first.Scalar();
    const std::string marker = r.Name(kv.first, pk);
    const std::string path = Resolve(r.file(), r.String(kv.second, pk));
    CheckReadable(r, kv.second, pk, path);
    d->position_tables.emplace_back(marker, path);
  }
  if (node["sequence"]) {
    d->sequence_table = Resolve(r.file(), r.String(node["sequence"], key + ".sequence"));
    CheckReadable(r, node["sequence"], key + ".sequence", d->sequence_table);
  }
  if (const YAML::Node units = node["units"]) {
    r.CheckKeys(units, key + ".units", {"length", "angle"});
    try {
      if (units["length"]) d->table_length_unit = LengthUnit(r.String(units["length"], key + ".units.length"));
      if (units["angle"]) d->table_angle_unit = AngleUnit(r.String(units["angle"], key + ".units.angle"));
    } catch (const std::invalid_argument& e) {
      r.Fail(units, key + ".units", e.what());
    }
  }
  d->summary = "measured: tables " + d->file_as_written + " (joints, " + d->table_angle_unit.name + ") and " +
               std::to_string(d->position_tables.size()) + " marker table(s) (" + d->table_length_unit.name + ")" +
               (d->sequence_table.empty()
                    ? ""
                    : ", previous poses from the unfiltered sequence " + r.String(node["sequence"], key + ".sequence"));
}

DatasetSpec ReadDatasetSpec(const Reader& r, const YAML::Node& node, const std::string& key, int dof) {
  r.CheckKeys(node, key, {"name", "simulate", "vary", "file", "tables", "split", "iso9283"});
  DatasetSpec d;
  if (!node["name"]) r.Fail(node, key, "missing key 'name'");
  d.name = r.Name(node["name"], key + ".name");
  if ((node["simulate"] ? 1 : 0) + (node["file"] ? 1 : 0) + (node["tables"] ? 1 : 0) > 1) {
    r.Fail(node, key, "give one of 'simulate', 'file' or 'tables'");
  }
  if (node["simulate"]) {
    ReadSimulator(r, node["simulate"], key + ".simulate", dof, &d);
    if (node["split"])
      r.Fail(node["split"], key + ".split", "a split applies to measured data ('file', 'tables') only");
    if (node["iso9283"]) r.Fail(node["iso9283"], key + ".iso9283", "on simulated data, ISO 9283 is a validation set");
    if (node["vary"]) ReadVary(r, node["vary"], key + ".vary", &d);
    return d;
  }
  if (!node["file"] && !node["tables"]) r.Fail(node, key, "missing key 'simulate', 'file' or 'tables'");
  d.simulated = false;
  if (node["vary"]) r.Fail(node["vary"], key + ".vary", "only simulated datasets can sweep a knob");
  if (node["file"]) {
    d.file_as_written = r.String(node["file"], key + ".file");
    d.file = Resolve(r.file(), d.file_as_written);
    d.summary = "measured: " + d.file_as_written;
    CheckReadable(r, node["file"], key + ".file", d.file);
  } else {
    ReadTables(r, node["tables"], key + ".tables", &d);
  }
  ReadSplit(r, node, key, &d);
  if (const YAML::Node iso = node["iso9283"]) {
    const std::string ik = key + ".iso9283";
    d.iso9283 = true;
    if (!iso.IsNull()) r.CheckKeys(iso, ik, {"tolerance", "angle_tolerance", "min_cycles"});
    if (iso["tolerance"]) d.iso_tolerance = r.Length(iso["tolerance"], ik + ".tolerance");
    if (!(d.iso_tolerance > 0)) r.Fail(iso["tolerance"], ik + ".tolerance", "expected a length > 0");
    if (iso["angle_tolerance"])
      d.iso_angle_tolerance = r.Number(iso["angle_tolerance"], ik + ".angle_tolerance") * M_PI / 180.0;
    if (!(d.iso_angle_tolerance > 0))
      r.Fail(iso["angle_tolerance"], ik + ".angle_tolerance", "expected an angle > 0 (deg)");
    if (iso["min_cycles"]) d.iso_min_cycles = r.Integer(iso["min_cycles"], ik + ".min_cycles", 2);
    d.summary += ", ISO 9283 of the test rows' poses visited at least " + std::to_string(d.iso_min_cycles) + " times";
  }
  return d;
}

// Options of a pipeline's methods: a map keyed by method names, or (one method) its options directly.
bool KeyedByMethod(const YAML::Node& options, const std::vector<std::string>& methods) {
  if (!options || !options.IsMap() || options.size() == 0) return false;
  for (const auto& kv : options) {
    if (std::find(methods.begin(), methods.end(), kv.first.Scalar()) == methods.end()) return false;
  }
  return true;
}

YAML::Node MethodOptions(const YAML::Node& options, const std::vector<std::string>& methods, size_t i) {
  if (!options || options.IsNull()) return YAML::Node();
  if (!KeyedByMethod(options, methods)) return options;
  const YAML::Node n = options[methods[i]];  // missing: an invalid node, which later uses throw on
  return n.IsDefined() ? n : YAML::Node();
}

// Creates the method once so that unknown options fail here, at their line.
template <typename RegistryT>
void CheckMethod(const Reader& r, const RegistryT& registry, const YAML::Node& at, const YAML::Node& options,
                 const std::string& key, const std::string& method) {
  try {
    registry.Get(method);
    registry.Create(method, options);
  } catch (const std::invalid_argument& e) {
    r.Fail(Given(options) ? options : at, key, e.what());
  }
}

std::vector<std::string> SplitMethods(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    std::string m = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    m.erase(0, m.find_first_not_of(' '));
    m.erase(m.find_last_not_of(' ') + 1);
    out.push_back(m);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string JoinMethods(const std::vector<std::string>& methods) {
  std::string s;
  for (const auto& m : methods) s += (s.empty() ? "" : "+") + m;
  return s;
}

PipelineSpec ReadPipeline(const Reader& r, const YAML::Node& node, const std::string& key,
                          const EstimatorRegistry& registry) {
  PipelineSpec p;
  if (node.IsMap()) {
    r.CheckKeys(node, key, {"name", "method", "options", "datasets"});
    if (!node["method"]) r.Fail(node, key, "missing key 'method'");
    if (node["datasets"]) {
      r.ExpectSequence(node["datasets"], key + ".datasets");
      for (size_t i = 0; i < node["datasets"].size(); ++i) {
        p.datasets.push_back(r.Name(node["datasets"][i], key + ".datasets[" + std::to_string(i) + "]"));
      }
    }
  } else if (!node.IsScalar()) {
    r.Fail(node, key, "expected a method name or a map with 'method'");
  }
  // (yaml-cpp's Node::operator= rebinds shared data, so nodes here are only ever copy-constructed.)
  const YAML::Node method = node.IsMap() ? node["method"] : node;
  const YAML::Node options = node.IsMap() ? node["options"] : YAML::Node();
  const std::string mk = node.IsMap() ? key + ".method" : key;
  p.methods = SplitMethods(r.String(method, mk));
  for (const auto& m : p.methods) {
    if (m.empty()) r.Fail(method, mk, "empty method name in '" + method.Scalar() + "'");
  }
  if (Given(options)) {
    r.ExpectMap(options, key + ".options");
    if (p.methods.size() > 1 && !KeyedByMethod(options, p.methods)) {
      r.Fail(options, key + ".options", "with several methods, the options must be keyed by method name");
    }
  }
  for (size_t i = 0; i < p.methods.size(); ++i) {
    const YAML::Node o = MethodOptions(options, p.methods, i);
    CheckMethod(r, registry, method, o, Given(options) ? key + ".options" : mk, p.methods[i]);
    p.options_yaml.push_back(OptionsText(o));
  }
  p.name = node.IsMap() && node["name"] ? r.Name(node["name"], key + ".name") : JoinMethods(p.methods);
  return p;
}

CompensatorSpec ReadCompensator(const Reader& r, const YAML::Node& node, const std::string& key,
                                const CompensatorRegistry& registry) {
  CompensatorSpec c;
  if (node.IsMap()) {
    r.CheckKeys(node, key, {"name", "method", "options"});
    if (!node["method"]) r.Fail(node, key, "missing key 'method'");
    if (node["options"]) r.ExpectMap(node["options"], key + ".options");
  } else if (!node.IsScalar()) {
    r.Fail(node, key, "expected a method name or a map with 'method'");
  }
  const YAML::Node method = node.IsMap() ? node["method"] : node;
  const YAML::Node options = node.IsMap() ? node["options"] : YAML::Node();
  const std::string mk = node.IsMap() ? key + ".method" : key;
  c.method = r.Name(method, mk);
  c.options_yaml = OptionsText(options);
  CheckMethod(r, registry, method, options, Given(options) ? key + ".options" : mk, c.method);
  c.name = node.IsMap() && node["name"] ? r.Name(node["name"], key + ".name") : c.method;
  return c;
}

ValidationSpec ReadValidation(const Reader& r, const YAML::Node& node, const std::string& key, const Robot& nominal) {
  r.CheckKeys(node, key, {"name", "random_targets", "orientation", "joint_limits", "iso9283"});
  ValidationSpec v;
  if (!node["name"]) r.Fail(node, key, "missing key 'name'");
  v.name = r.Name(node["name"], key + ".name");
  if (node["orientation"]) v.orientation = r.Bool(node["orientation"], key + ".orientation");
  const int n = nominal.dof();
  if (node["random_targets"] && node["iso9283"]) r.Fail(node, key, "give either 'random_targets' or 'iso9283'");
  if (node["random_targets"]) {
    v.kind = ValidationSpec::Kind::kRandom;
    v.count = r.Integer(node["random_targets"], key + ".random_targets", 1);
    if (node["joint_limits"]) {
      const YAML::Node l = node["joint_limits"];
      const std::string lk = key + ".joint_limits";
      r.ExpectSequence(l, lk);
      if (static_cast<int>(l.size()) != n) r.Fail(l, lk, "expected " + std::to_string(n) + " [min, max] pairs (deg)");
      for (int j = 0; j < n; ++j) {
        const std::vector<double> mm = r.Numbers(l[j], lk + "[" + std::to_string(j) + "]");
        if (mm.size() != 2 || !(mm[0] <= mm[1]))
          r.Fail(l[j], lk + "[" + std::to_string(j) + "]", "expected [min, max] with min <= max");
        v.joint_limits.emplace_back(mm[0] * M_PI / 180.0, mm[1] * M_PI / 180.0);
      }
    }
    v.summary = std::to_string(v.count) + " random " + (v.orientation ? "poses" : "positions") +
                (v.joint_limits.empty() ? " within the joint limits" : " within the given joint ranges");
  } else if (node["iso9283"]) {
    v.kind = ValidationSpec::Kind::kIso9283;
    if (node["joint_limits"]) r.Fail(node["joint_limits"], key + ".joint_limits", "applies to random targets only");
    const YAML::Node s = node["iso9283"];
    const std::string sk = key + ".iso9283";
    if (!s.IsNull()) {
      r.CheckKeys(s, sk, {"side", "center_configuration", "cycles", "joint_noise", "measurement_noise"});
      if (s["side"]) v.iso.side = r.Length(s["side"], sk + ".side");
      if (!(v.iso.side > 0)) r.Fail(s["side"], sk + ".side", "expected a length > 0");
      if (s["center_configuration"]) {
        v.iso.center_configuration = r.Angles(s["center_configuration"], sk + ".center_configuration", n);
      }
      if (s["cycles"]) v.iso.cycles = r.Integer(s["cycles"], sk + ".cycles", 2);
      if (s["joint_noise"]) {
        v.iso.joint_noise = r.Number(s["joint_noise"], sk + ".joint_noise") * M_PI / 180.0;
        if (v.iso.joint_noise < 0) r.Fail(s["joint_noise"], sk + ".joint_noise", "expected >= 0");
      }
      if (s["measurement_noise"]) v.iso.measurement_noise = r.Length(s["measurement_noise"], sk + ".measurement_noise");
    }
    char text[200];
    std::snprintf(text, sizeof(text), "ISO 9283 cube of %.4g mm, poses P1..P5, %d cycles, joint noise %.4g deg",
                  v.iso.side * 1e3, v.iso.cycles, v.iso.joint_noise * 180.0 / M_PI);
    v.summary = text;
  } else {
    r.Fail(node, key, "missing key 'random_targets' or 'iso9283'");
  }
  return v;
}

}  // namespace

bool PipelineSpec::RunsOn(const std::string& dataset) const {
  return datasets.empty() || std::find(datasets.begin(), datasets.end(), dataset) != datasets.end();
}

Study ParseStudy(const std::string& text, const std::string& source_path, const MethodRegistries& registries) {
  const Reader r(source_path);
  YAML::Node loaded;
  try {
    loaded = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    ThrowInputError(source_path, e.mark.line + 1, e.mark.column + 1, "invalid YAML: " + e.msg);
  }
  const YAML::Node root = loaded;  // const: operator[] looks up, never inserts
  if (!root.IsMap())
    ThrowInputError(source_path, 1, 1, "expected a study (a YAML map with name, robots, datasets, ...)");
  r.CheckKeys(root, "",
              {"name", "description", "seed", "trials", "threads", "robots", "datasets", "estimators", "compensators",
               "validation"});
  Study s;
  s.source = source_path;
  s.text_hash = HashLabel(text);
  if (!root["name"]) r.Fail(root, "name", "missing key (the study's name)");
  s.name = r.String(root["name"], "name");
  if (root["description"]) s.description = r.String(root["description"], "description");
  if (root["seed"]) {
    const double seed = r.Number(root["seed"], "seed");
    if (seed != std::floor(seed) || seed < 0 || seed > 9.0e15) r.Fail(root["seed"], "seed", "expected an integer >= 0");
    s.seed = static_cast<uint64_t>(seed);
  }
  if (root["trials"]) s.trials = r.Integer(root["trials"], "trials", 1);
  if (root["threads"]) s.threads = r.Integer(root["threads"], "threads", 0);

  if (!root["robots"]) r.Fail(root, "robots", "missing key (robots: {nominal: ..., truth: ...})");
  const YAML::Node robots = root["robots"];
  r.CheckKeys(robots, "robots", {"nominal", "truth"});
  if (!robots["nominal"]) r.Fail(robots, "robots.nominal", "missing key (the controller's robot file)");
  s.nominal = ReadRobot(r, robots["nominal"], "robots.nominal", source_path);
  if (robots["truth"]) {
    s.truth = ReadRobot(r, robots["truth"], "robots.truth", source_path);
    if (s.truth->robot.dof() != s.nominal.robot.dof()) {
      r.Fail(robots["truth"], "robots.truth",
             "has " + std::to_string(s.truth->robot.dof()) + " joints, the nominal " +
                 std::to_string(s.nominal.robot.dof()));
    }
    if (s.truth->robot.drives.has_value() != s.nominal.robot.drives.has_value()) {
      r.Fail(robots["truth"], "robots.truth", "give drives in both robots or in neither");
    }
  }
  const int dof = s.nominal.robot.dof();

  if (!root["datasets"]) r.Fail(root, "datasets", "missing key (at least one dataset)");
  r.ExpectSequence(root["datasets"], "datasets");
  if (root["datasets"].size() == 0) r.Fail(root["datasets"], "datasets", "expected at least one dataset");
  std::set<std::string> names;
  for (size_t i = 0; i < root["datasets"].size(); ++i) {
    const std::string key = "datasets[" + std::to_string(i) + "]";
    const YAML::Node node = root["datasets"][i];
    DatasetSpec d = ReadDatasetSpec(r, node, key, dof);
    if (!names.insert(d.name).second) r.Fail(node["name"], key + ".name", "duplicate dataset name '" + d.name + "'");
    if (d.simulated && !s.truth) r.Fail(node, key, "a simulated dataset needs robots.truth");
    s.datasets.push_back(std::move(d));
  }

  s.pipelines.push_back({"none", {"none"}, {""}, {}});
  registries.estimators->Get("none");
  if (root["estimators"]) {
    r.ExpectSequence(root["estimators"], "estimators");
    for (size_t i = 0; i < root["estimators"].size(); ++i) {
      const std::string key = "estimators[" + std::to_string(i) + "]";
      const YAML::Node node = root["estimators"][i];
      PipelineSpec p = ReadPipeline(r, node, key, *registries.estimators);
      for (size_t k = 0; k < p.datasets.size(); ++k) {
        if (!names.count(p.datasets[k])) {
          r.Fail(node["datasets"][k], key + ".datasets[" + std::to_string(k) + "]",
                 "unknown dataset '" + p.datasets[k] + "'");
        }
      }
      if (p.name == "none" && p.methods == std::vector<std::string>{"none"}) continue;  // the baseline runs anyway
      for (const auto& q : s.pipelines) {
        if (q.name == p.name) r.Fail(node, key, "duplicate estimator name '" + p.name + "' (give each a 'name')");
      }
      s.pipelines.push_back(std::move(p));
    }
  }

  s.compensators.push_back({"none", "none", ""});
  registries.compensators->Get("none");
  if (root["compensators"]) {
    r.ExpectSequence(root["compensators"], "compensators");
    for (size_t i = 0; i < root["compensators"].size(); ++i) {
      const std::string key = "compensators[" + std::to_string(i) + "]";
      const YAML::Node node = root["compensators"][i];
      CompensatorSpec c = ReadCompensator(r, node, key, *registries.compensators);
      if (c.name == "none" && c.method == "none") continue;
      for (const auto& q : s.compensators) {
        if (q.name == c.name) r.Fail(node, key, "duplicate compensator name '" + c.name + "' (give each a 'name')");
      }
      s.compensators.push_back(std::move(c));
    }
  }

  if (root["validation"]) {
    r.ExpectSequence(root["validation"], "validation");
    std::set<std::string> vnames;
    for (size_t i = 0; i < root["validation"].size(); ++i) {
      const std::string key = "validation[" + std::to_string(i) + "]";
      const YAML::Node node = root["validation"][i];
      ValidationSpec v = ReadValidation(r, node, key, s.nominal.robot);
      if (!vnames.insert(v.name).second)
        r.Fail(node["name"], key + ".name", "duplicate validation name '" + v.name + "'");
      s.validation.push_back(std::move(v));
    }
  }
  bool any_simulated = false;
  for (const auto& d : s.datasets) any_simulated |= d.simulated;
  if (any_simulated && s.validation.empty()) {
    r.Fail(root, "validation",
           "missing key: simulated datasets are scored on validation targets (e.g. "
           "validation: [{name: random, random_targets: 100}])");
  }
  return s;
}

Study ReadStudyFile(const std::string& path, const MethodRegistries& registries) {
  return ParseStudy(ReadFileToString(path), path, registries);
}

}  // namespace kincal
