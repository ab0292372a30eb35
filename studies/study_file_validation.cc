// Study file: the validation sets of simulated datasets (study.h): random targets or the ISO 9283 cube.
#include "studies/study_file_reader.h"
#include "studies/study_options.h"

namespace kincal::study_file {

ValidationSpec ReadValidation(const Reader& r, const YAML::Node& node, const std::string& key, const Robot& nominal) {
  r.CheckKeys(node, key, {"name", "random_targets", "orientation", "joint_limits", "iso9283"});
  ValidationSpec v;
  if (!node["name"]) r.Fail(node, key, "missing key 'name'");
  v.name = r.Name(node["name"], key + ".name");
  // The table's keys alone (the nodes keep their places in the file).
  YAML::Node own(YAML::NodeType::Map);
  for (const OptionDoc& d : ValidationSpec::Table().Docs()) {
    if (node[d.key]) own[d.key] = node[d.key];
  }
  const ValidationSpec read = ReadOptions(r, ValidationSpec::Table(), own, key);
  v.orientation = read.orientation;
  const int n = nominal.dof();
  if (node["random_targets"] && node["iso9283"]) r.Fail(node, key, "give either 'random_targets' or 'iso9283'");
  if (node["random_targets"]) {
    v.kind = ValidationSpec::Kind::kRandom;
    v.count = read.count;
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
    v.iso = ReadOptions(r, Iso9283Spec::Table(), s, sk);
    const int given = static_cast<int>(v.iso.center_configuration.size());
    if (given != 0 && given != n) {
      r.Fail(s["center_configuration"], sk + ".center_configuration",
             "expected " + std::to_string(n) + " angles (deg), got " + std::to_string(given));
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

}  // namespace kincal::study_file
