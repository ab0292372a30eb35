// Study file parser (the schema is documented in study.h and examples/studies/): the top level and the
// robots here, the sections in study_file_datasets.cc, study_file_methods.cc and study_file_validation.cc.
#include <filesystem>
#include <set>

#include "framework/atomic_file.h"
#include "robot/robot_file.h"
#include "studies/study_file_reader.h"
#include "studies/study_options.h"

namespace kincal {
namespace study_file {

std::string Resolve(const std::string& study_path, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(study_path).parent_path() / p).lexically_normal().string();
}

}  // namespace study_file

namespace {

using study_file::Reader;

RobotSpec ReadRobot(const Reader& r, const YAML::Node& node, const std::string& key, const std::string& study_path) {
  RobotSpec spec;
  try {
    if (node.IsScalar()) {
      spec.source = node.Scalar();
      spec.robot = ReadRobotFile(study_file::Resolve(study_path, node.Scalar()));
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

// name, description, seed, trials, threads.
void ReadSettings(const Reader& r, const YAML::Node& root, Study* s) {
  if (!root["name"]) r.Fail(root, "name", "missing key (the study's name)");
  s->name = r.String(root["name"], "name");
  if (root["description"]) s->description = r.String(root["description"], "description");
  // The settings' keys alone, as their table reads them (the nodes keep their places in the file).
  YAML::Node settings(YAML::NodeType::Map);
  for (const OptionDoc& d : StudySettings::Table().Docs()) {
    if (root[d.key]) settings[d.key] = root[d.key];
  }
  const StudySettings read = study_file::ReadOptions(r, StudySettings::Table(), settings, "");
  s->seed = read.seed;
  s->trials = read.trials;
  s->threads = read.threads;
}

void ReadRobots(const Reader& r, const YAML::Node& root, const std::string& source_path, Study* s) {
  if (!root["robots"]) r.Fail(root, "robots", "missing key (robots: {nominal: ..., truth: ...})");
  const YAML::Node robots = root["robots"];
  r.CheckKeys(robots, "robots", {"nominal", "truth"});
  if (!robots["nominal"]) r.Fail(robots, "robots.nominal", "missing key (the controller's robot file)");
  s->nominal = ReadRobot(r, robots["nominal"], "robots.nominal", source_path);
  if (!robots["truth"]) return;
  s->truth = ReadRobot(r, robots["truth"], "robots.truth", source_path);
  if (s->truth->robot.dof() != s->nominal.robot.dof()) {
    r.Fail(robots["truth"], "robots.truth",
           "has " + std::to_string(s->truth->robot.dof()) + " joints, the nominal " +
               std::to_string(s->nominal.robot.dof()));
  }
  if (s->truth->robot.drives.has_value() != s->nominal.robot.drives.has_value()) {
    r.Fail(robots["truth"], "robots.truth", "give drives in both robots or in neither");
  }
}

// Calls read(entry, "section[i]") for each entry of the list `section` of the top level; none when absent.
template <typename Read>
void ForEachEntry(const Reader& r, const YAML::Node& root, const std::string& section, Read read) {
  if (!root[section]) return;
  const YAML::Node list = root[section];
  r.ExpectSequence(list, section);
  for (size_t i = 0; i < list.size(); ++i) read(list[i], section + "[" + std::to_string(i) + "]");
}

void ReadDatasets(const Reader& r, const YAML::Node& root, Study* s) {
  if (!root["datasets"]) r.Fail(root, "datasets", "missing key (at least one dataset)");
  r.ExpectSequence(root["datasets"], "datasets");
  if (root["datasets"].size() == 0) r.Fail(root["datasets"], "datasets", "expected at least one dataset");
  std::set<std::string> names;
  ForEachEntry(r, root, "datasets", [&](const YAML::Node& node, const std::string& key) {
    DatasetSpec d = study_file::ReadDatasetSpec(r, node, key, s->nominal.robot.dof());
    if (!names.insert(d.name).second) r.Fail(node["name"], key + ".name", "duplicate dataset name '" + d.name + "'");
    if (d.simulated && !s->truth) r.Fail(node, key, "a simulated dataset needs robots.truth");
    s->datasets.push_back(std::move(d));
  });
}

// The baseline `none` first, then the file's pipelines.
void ReadPipelines(const Reader& r, const YAML::Node& root, const EstimatorRegistry& registry, Study* s) {
  s->pipelines.push_back({"none", {"none"}, {""}, {}});
  registry.Get("none");
  ForEachEntry(r, root, "estimators", [&](const YAML::Node& node, const std::string& key) {
    PipelineSpec p = study_file::ReadPipeline(r, node, key, registry);
    for (size_t k = 0; k < p.datasets.size(); ++k) {
      const auto& datasets = s->datasets;
      if (std::none_of(datasets.begin(), datasets.end(),
                       [&](const DatasetSpec& d) { return d.name == p.datasets[k]; })) {
        r.Fail(node["datasets"][k], key + ".datasets[" + std::to_string(k) + "]",
               "unknown dataset '" + p.datasets[k] + "'");
      }
    }
    if (p.name == "none" && p.methods == std::vector<std::string>{"none"}) return;  // the baseline runs anyway
    for (const auto& q : s->pipelines) {
      if (q.name == p.name) r.Fail(node, key, "duplicate estimator name '" + p.name + "' (give each a 'name')");
    }
    s->pipelines.push_back(std::move(p));
  });
}

// The baseline `none` first, then the file's compensators.
void ReadCompensators(const Reader& r, const YAML::Node& root, const CompensatorRegistry& registry, Study* s) {
  s->compensators.push_back({"none", "none", ""});
  registry.Get("none");
  ForEachEntry(r, root, "compensators", [&](const YAML::Node& node, const std::string& key) {
    CompensatorSpec c = study_file::ReadCompensator(r, node, key, registry);
    if (c.name == "none" && c.method == "none") return;
    for (const auto& q : s->compensators) {
      if (q.name == c.name) r.Fail(node, key, "duplicate compensator name '" + c.name + "' (give each a 'name')");
    }
    s->compensators.push_back(std::move(c));
  });
}

void ReadValidations(const Reader& r, const YAML::Node& root, Study* s) {
  std::set<std::string> names;
  ForEachEntry(r, root, "validation", [&](const YAML::Node& node, const std::string& key) {
    ValidationSpec v = study_file::ReadValidation(r, node, key, s->nominal.robot);
    if (!names.insert(v.name).second) r.Fail(node["name"], key + ".name", "duplicate validation name '" + v.name + "'");
    s->validation.push_back(std::move(v));
  });
  const bool any_simulated =
      std::any_of(s->datasets.begin(), s->datasets.end(), [](const DatasetSpec& d) { return d.simulated; });
  if (any_simulated && s->validation.empty()) {
    r.Fail(root, "validation",
           "missing key: simulated datasets are scored on validation targets (e.g. "
           "validation: [{name: random, random_targets: 100}])");
  }
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
  ReadSettings(r, root, &s);
  ReadRobots(r, root, source_path, &s);
  ReadDatasets(r, root, &s);
  ReadPipelines(r, root, *registries.estimators, &s);
  ReadCompensators(r, root, *registries.compensators, &s);
  ReadValidations(r, root, &s);
  return s;
}

Study ReadStudyFile(const std::string& path, const MethodRegistries& registries) {
  return ParseStudy(ReadFileToString(path), path, registries);
}

}  // namespace kincal
