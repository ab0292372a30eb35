#pragma once
// The option sections of study files, each declared once in an OptionTable (framework/options.h): the
// study file parser reads them through it (every bad value named by its path, line and column), IsValid
// checks the same requirements, and StudyOptionDocs lists them (key, type, default, doc).
//   (top level)             StudySettings: seed, trials, threads
//   datasets[].simulate     SimulateOptions: SimulatorOptions::Table() (robot/simulator.h) and `marker`
//   datasets[].iso9283      MeasuredIso9283Spec::Table() (study.h)
//   validation[]            ValidationSpec::Table() (study.h): random_targets, orientation
//   validation[].iso9283    Iso9283Spec::Table() (study.h)
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "framework/options.h"
#include "robot/simulator.h"

namespace kincal {

// The top level's run settings (the study's other keys are sections of their own).
struct StudySettings {
  uint64_t seed = 1;  // every random stream derives from it
  int trials = 1;     // Monte Carlo trials
  int threads = 0;    // 0: every core; `--threads` overrides
  static const OptionTable<StudySettings>& Table();
  bool IsValid(std::string* why) const { return Table().Validate(*this, why); }
};

// A dataset's `simulate:` map: the simulator's keys and the measured point on the flange.
struct SimulateOptions {
  SimulatorOptions simulator;
  std::vector<double> marker;  // mm, [x, y, z]: replaces the tool of the nominal and the truth; empty: none
  static const OptionTable<SimulateOptions>& Table();
  bool IsValid(std::string* why) const { return Table().Validate(*this, why); }
};

// Every section above as (its path in a study file, its keys).
std::vector<std::pair<std::string, std::vector<OptionDoc>>> StudyOptionDocs();

}  // namespace kincal
