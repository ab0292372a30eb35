#pragma once
// Shared helpers of the geometric and ratio_regression tests: the seed's protocol in simulation.
#include <string>
#include <vector>

#include "framework/dataset.h"
#include "estimators/estimator.h"
#include "robot/robot.h"
#include "robot/simulator.h"

namespace kincal::testing {

// The seed's sweep protocol (20 stops 2 deg apart, joints n..1 from q = 0) on `truth`, controlled by
// `nominal`, with `noise` m per axis.
inline Dataset SeedSweeps(const Robot& nominal, const Robot& truth, double noise, uint64_t seed, int stops = 20,
                          double step_deg = 2.0) {
  SimulatorOptions o;
  o.stops = stops;
  o.step = step_deg * M_PI / 180.0;
  o.noise_sigma = noise;
  o.seed = seed;
  return Simulate(nominal, truth, o);
}

inline std::vector<EstimationReport> Identify(const Robot& nominal, const Dataset& data, Robot* identified,
                                              const std::string& geometric_options = "{}") {
  const YAML::Node options = YAML::Load(geometric_options);
  return RunPipeline({"geometric", "ratio_regression"}, {options, options}, nominal, data, identified);
}

}  // namespace kincal::testing
