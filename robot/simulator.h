#pragma once
// Simulator: datasets from a known truth. The controller (the nominal robot) commands joint angles and
// converts them to motor counts with its nominal ratios; the truth robot turns by what those counts
// mean with its real ratios; the instrument measures the truth's marker with noise.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "framework/options.h"
#include "robot/robot.h"
#include "robot/simulator_instruments.h"

namespace kincal {

struct SimulatorOptions {
  // "sweep": the seed's protocol (METHOD.md section 2): from `start`, joints swept one at a time in
  // `sweep_order` (default n..1), each through `stops` stops `step` apart (the first stop at the joint's
  // current angle), the others holding their current angle, so a joint swept earlier stays where its
  // sweep ended. "random": `poses` configurations uniform within the nominal robot's joint limits.
  std::string protocol = "sweep";
  int poses = 100;                   // random protocol
  int stops = 20;                    // sweep protocol, stops per joint
  double step = 2.0 * M_PI / 180.0;  // sweep protocol, rad between stops
  Eigen::VectorXd start;             // calibration configuration (commanded); empty = zeros
  std::vector<int> sweep_order;      // 1-based joints; empty = n, n-1, ..., 1
  // Position noise per axis: sigma = noise_sigma + noise_range_coefficient * distance to the instrument
  // (the measurement-frame origin), m and m/m. A laser tracker is roughly 5e-6 m + 5e-6 m/m.
  double noise_sigma = 0.0;
  double noise_range_coefficient = 0.0;
  bool orientation = false;        // also record the tool orientation (qw, qx, qy, qz)
  double orientation_noise = 0.0;  // rad, per axis of a small rotation
  // What the rows read (robot/simulator_instruments.h). For plane and socket the configurations are the
  // contacts found (`poses` of them, random protocol only).
  InstrumentOptions instrument;
  // Markers to record at every pose (ids of the truth robot's `markers`); empty = the tool origin, or
  // every marker when the truth robot lists some.
  std::vector<std::string> markers;
  uint64_t seed = 1;
  // Units the dataset will be written in.
  Unit length_unit = {"mm", 1e-3};
  Unit angle_unit = {"deg", M_PI / 180.0};

  // The keys a file gives (a study's `simulate:` map): protocol, poses, stops, step (deg), start (deg),
  // order, noise and noise_range (lengths, mm when plain), orientation, orientation_noise (deg), and the
  // instrument's keys (InstrumentOptions::Table). markers, seed and the units are set by the caller. Validation (IsValid) checks the same requirements.
  static const OptionTable<SimulatorOptions>& Table();
  bool IsValid(std::string* why) const;
};

// Throws std::invalid_argument for invalid options or robots that do not match (joint count, drives on
// one side only).
Dataset Simulate(const Robot& nominal, const Robot& truth, const SimulatorOptions& options);

}  // namespace kincal
