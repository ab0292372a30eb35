// The plan of a study: dataset variants, work items in their fixed order, seeds, and the manifest.
#include <cmath>
#include <cstdio>

#include "framework/random.h"
#include "studies/study.h"

namespace kincal {

uint64_t HashLabel(const std::string& text) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::vector<DatasetVariant> Variants(const Study& study) {
  std::vector<DatasetVariant> out;
  for (size_t d = 0; d < study.datasets.size(); ++d) {
    const DatasetSpec& spec = study.datasets[d];
    if (!spec.vary) {
      DatasetVariant v;
      v.dataset = static_cast<int>(d);
      v.label = spec.name;
      v.simulator = spec.simulator;
      out.push_back(v);
      continue;
    }
    const KnobSweep& k = *spec.vary;
    for (size_t i = 0; i < k.values.size(); ++i) {
      DatasetVariant v;
      v.dataset = static_cast<int>(d);
      v.variant = static_cast<int>(i);
      v.simulator = spec.simulator;
      v.label = spec.name + "[" + k.knob + "=" + k.texts[i] + "]";
      const double x = k.values[i];
      if (k.knob == "noise") {
        v.knob = "noise_um";
        v.knob_value = x * 1e6;
        v.simulator.noise_sigma = x;
      } else if (k.knob == "noise_range") {
        v.knob = "noise_range_um_per_m";
        v.knob_value = x * 1e6;
        v.simulator.noise_range_coefficient = x;
      } else if (k.knob == "poses") {
        v.knob = "poses";
        v.knob_value = x;
        v.simulator.poses = static_cast<int>(x);
      } else if (k.knob == "stops") {
        v.knob = "stops";
        v.knob_value = x;
        v.simulator.stops = static_cast<int>(x);
      } else if (k.knob == "step") {
        v.knob = "step_deg";
        v.knob_value = x * 180.0 / M_PI;
        v.simulator.step = x;
      } else {  // arc: the whole sweep of each joint
        v.knob = "arc_deg";
        v.knob_value = x * 180.0 / M_PI;
        v.simulator.step = x / (v.simulator.stops - 1);
      }
      out.push_back(v);
    }
  }
  return out;
}

std::vector<WorkItem> WorkItems(const Study& study, const std::vector<DatasetVariant>& variants) {
  std::vector<WorkItem> items;
  for (size_t v = 0; v < variants.size(); ++v) {
    const std::string& dataset = study.datasets[variants[v].dataset].name;
    for (int t = 0; t < study.trials; ++t) {
      for (size_t p = 0; p < study.pipelines.size(); ++p) {
        if (!study.pipelines[p].RunsOn(dataset)) continue;
        WorkItem w;
        w.index = static_cast<int>(items.size());
        w.variant = static_cast<int>(v);
        w.trial = t;
        w.pipeline = static_cast<int>(p);
        items.push_back(w);
      }
    }
  }
  return items;
}

uint64_t DatasetSeed(const Study& study, const DatasetVariant& variant, int trial) {
  const uint64_t dataset = Rng::Derive(study.seed, HashLabel("dataset:" + study.datasets[variant.dataset].name));
  return Rng::Derive(Rng::Derive(dataset, static_cast<uint64_t>(variant.variant)), static_cast<uint64_t>(trial));
}

uint64_t ValidationSeed(const Study& study, const ValidationSpec& validation) {
  return Rng::Derive(study.seed, HashLabel("validation:" + validation.name));
}

nlohmann::json StudyManifest(const Study& study, const std::vector<DatasetVariant>& variants, int num_items) {
  nlohmann::json j;
  j["format"] = "kincal study results v1";
  j["name"] = study.name;
  j["description"] = study.description;
  j["seed"] = study.seed;
  j["trials"] = study.trials;
  j["items"] = num_items;
  j["robots"]["nominal"] = {{"name", study.nominal.robot.name}, {"source", study.nominal.source}};
  if (study.truth) j["robots"]["truth"] = {{"name", study.truth->robot.name}, {"source", study.truth->source}};
  j["datasets"] = nlohmann::json::array();
  for (const auto& d : study.datasets) {
    nlohmann::json dj = {{"name", d.name}, {"simulated", d.simulated}, {"summary", d.summary}};
    if (d.vary) dj["vary"] = {{"knob", d.vary->knob}, {"values", d.vary->texts}};
    if (d.simulated) dj["instrument"] = d.simulator.instrument.instrument;
    if (d.iso9283) dj["iso9283"] = true;
    j["datasets"].push_back(dj);
  }
  j["variants"] = nlohmann::json::array();
  for (const auto& v : variants) {
    j["variants"].push_back(
        {{"dataset", study.datasets[v.dataset].name},
         {"label", v.label},
         {"knob", v.knob},
         {"knob_value", std::isnan(v.knob_value) ? nlohmann::json(nullptr) : nlohmann::json(v.knob_value)}});
  }
  j["estimators"] = nlohmann::json::array();
  for (const auto& p : study.pipelines) {
    j["estimators"].push_back(
        {{"name", p.name}, {"methods", p.methods}, {"options", p.options_yaml}, {"datasets", p.datasets}});
  }
  j["compensators"] = nlohmann::json::array();
  for (const auto& c : study.compensators) {
    j["compensators"].push_back({{"name", c.name}, {"method", c.method}, {"options", c.options_yaml}});
  }
  j["validation"] = nlohmann::json::array();
  for (const auto& v : study.validation) {
    j["validation"].push_back({{"name", v.name},
                               {"kind", v.kind == ValidationSpec::Kind::kIso9283 ? "iso9283" : "random"},
                               {"summary", v.summary}});
  }
  return j;
}

}  // namespace kincal
