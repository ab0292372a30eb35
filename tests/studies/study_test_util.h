#pragma once
// Small studies for the tests: seed robots, few poses and targets, so that each run takes a fraction of a
// second (also under the sanitizers).
#include <cstdint>
#include <string>

#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal::testing {

// The robots block, with absolute paths to the example robots.
inline std::string SeedRobotsYaml() {
  return "robots:\n  nominal: " + SourcePath("examples/robots/seed_nominal.yaml") +
         "\n  truth: " + SourcePath("examples/robots/seed_identified.yaml") + "\n";
}

// Two datasets, the test-double methods, random targets and the ISO cube, two trials.
inline std::string SmallStudyYaml() {
  return "name: small\n"
         "seed: 7\n"
         "trials: 2\n" +
         SeedRobotsYaml() +
         "datasets:\n"
         "  - name: sweep\n"
         "    simulate: {protocol: sweep, stops: 4, step: 3, noise: 10um}\n"
         "  - name: random\n"
         "    simulate: {protocol: random, poses: 24, noise: 10um}\n"
         "estimators:\n"
         "  - base_kabsch\n"
         "  - {name: oracle, method: oracle, datasets: [random]}\n"
         "  - {method: throws, datasets: [sweep]}\n"
         "compensators:\n"
         "  - jacobian_ik\n"
         "validation:\n"
         "  - {name: targets, random_targets: 12}\n"
         "  - {name: cube, iso9283: {side: 150mm, cycles: 6, joint_noise: 0.002}}\n";
}

// Measurements of the seed's truth at `poses` random configurations with `noise` per axis (m), as a
// measured dataset of a study would hold them.
inline Dataset SeedMeasurements(int poses, double noise, uint64_t seed = 1) {
  SimulatorOptions o;
  o.protocol = "random";
  o.poses = poses;
  o.noise_sigma = noise;
  o.seed = seed;
  return Simulate(SeedNominal(), SeedTruth(), o);
}

// The files of a study's output folder that must be byte-identical between runs of the same study
// (threads, shards, resumes); timings.csv and report.md hold wall-clock times.
inline const char* const kDeterministicFiles[] = {"study.json", "results.csv", "parameters.csv", "convergence.csv",
                                                  "iso9283.csv"};

// report.md without its Times section (wall-clock times differ between runs).
inline std::string ReportWithoutTimes(const std::string& dir) {
  const std::string report = ReadText(dir + "/report.md");
  const size_t begin = report.find("## Times"), end = report.find("## Files");
  return report.substr(0, begin) + report.substr(end);
}

}  // namespace kincal::testing
