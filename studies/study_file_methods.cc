// Study file: the estimator pipelines and the compensators (study.h). Each method is created once here so
// that its unknown or invalid options fail at their line.
#include <algorithm>

#include "studies/study_file_reader.h"

namespace kincal::study_file {
namespace {

std::string OptionsText(const YAML::Node& node) {
  if (!node || node.IsNull()) return "";
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node;
  return out.c_str();
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

}  // namespace

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

}  // namespace kincal::study_file
