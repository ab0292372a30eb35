#pragma once
// `kincal demo`: the seed's experiment (METHOD.md section 5) in simulation, with no file at hand. The arm
// of Table 1 with the nominal ratios is the controller; Table 2 with the identified ratios of Table 3 is
// the truth. Two datasets of the same size at laser-tracker noise: the seed's sweep protocol (each joint
// 20 stops 2 deg apart, 6..1) and random poses. Every registered estimator (sweep-based ones on the sweep
// dataset, the others on the random one) and every registered compensator; 10 random targets as in the
// seed, 1000 more, and the ISO 9283 cube; a few Monte Carlo trials.
#include <cstdint>
#include <string>

#include "studies/study.h"

namespace kincal {

// The demo's sizes, chosen so that it finishes in about a minute on 2 cores with every method.
struct DemoOptions {
  int trials = 3;            // Monte Carlo trials
  int seed_targets = 10;     // the seed's 10 random targets
  int extra_targets = 1000;  // "and 1000 more"
  int stops = 20;            // the seed's protocol: stops per joint (the random dataset matches 6 x stops)
  bool iso = true;           // the ISO 9283 cube
  uint64_t seed = 1;
  bool IsValid(std::string* why) const;
};

// The seed's robots as in examples/robots/seed_nominal.yaml and seed_identified.yaml.
std::string SeedNominalRobotYaml();
std::string SeedIdentifiedRobotYaml();

// The demo as a study file (robots inline), running what `registries` hold.
std::string DemoStudyYaml(const DemoOptions& options, const MethodRegistries& registries = MethodRegistries());

// The terminal summary of a finished demo folder: the seed's headline beside ours.
std::string DemoSummary(const std::string& dir);

}  // namespace kincal
