// Study file: the datasets (study.h): simulated (`simulate:`, a knob swept with `vary:`) or measured
// (`file:` or `tables:`, with their `split:` and optional `iso9283:`).
#include <algorithm>

#include "framework/atomic_file.h"
#include "studies/study_file_reader.h"
#include "studies/study_options.h"

namespace kincal::study_file {
namespace {

void ReadSimulator(const Reader& r, const YAML::Node& node, const std::string& key, int dof, DatasetSpec* d) {
  r.ExpectMap(node, key);
  const SimulateOptions read = ReadOptions(r, SimulateOptions::Table(), node, key);
  const SimulatorOptions& o = d->simulator = read.simulator;
  // What the table cannot know: the robot's joint count. (An empty list is the default, as documented.)
  const auto k = [&](const char* name) { return Reader::Join(key, name); };
  if (o.start.size() != 0 && o.start.size() != dof) {
    r.Fail(node["start"], k("start"),
           "expected " + std::to_string(dof) + " angles (deg), got " + std::to_string(o.start.size()));
  }
  for (int j : o.sweep_order) {
    if (j > dof) r.Fail(node["order"], k("order"), "expected joint numbers 1.." + std::to_string(dof));
  }
  if (!read.marker.empty()) d->marker = Eigen::Vector3d(read.marker[0], read.marker[1], read.marker[2]) * 1e-3;
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
  const InstrumentOptions& instrument = o.instrument;
  if (instrument.instrument == "partial") d->summary += ", a gauge reading " + instrument.axes;
  if (instrument.instrument == "distance" || instrument.Contacts()) {
    d->summary += ", " + instrument.instrument + " instrument (the truth's fixtures, or " +
                  std::to_string(instrument.fixtures) + " random ones)";
  }
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

}  // namespace

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
  if (node["iso9283"]) {
    d.iso9283 = true;
    d.iso = ReadOptions(r, MeasuredIso9283Spec::Table(), node["iso9283"], key + ".iso9283");
    d.summary += ", ISO 9283 of the test rows' poses visited at least " + std::to_string(d.iso.min_cycles) + " times";
  }
  return d;
}

}  // namespace kincal::study_file
