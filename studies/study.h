#pragma once
// Study: a comparison of calibration methods described in one YAML file (DESIGN.md data flow).
// Datasets x estimator pipelines x compensators x Monte Carlo trials, every combination scored by the
// same metrics on the same validation targets.
//
// Study file (v1). Lengths are numbers in mm or carry a unit ("10um", "0.5mm", "0.001m"); angles are
// degrees; paths are relative to the study file. Unknown keys, wrong types and values out of range are
// errors naming the key, line and column. The settings, `simulate` and the `iso9283` maps are declared
// once, in option tables (studies/study_options.h).
//
//   name: seed_comparison          # required; the report's title
//   description: free text         # optional
//   seed: 1                        # default 1; every random stream derives from it
//   trials: 5                      # default 1; Monte Carlo trials (new noise, new random poses each)
//   threads: 0                     # default 0 = every core; `--threads` overrides
//   robots:
//     nominal: ../robots/seed_nominal.yaml   # the controller's robot: a path, or an inline robot map
//     truth: ../robots/seed_identified.yaml  # the real arm of simulations; required by simulated datasets
//   datasets:                      # at least one
//     - name: sweep                # unique; letters, digits, '_', '-', '.'
//       simulate:                  # simulated (the `kincal simulate` knobs, SimulatorOptions)
//         protocol: sweep          # sweep | random
//         poses: 120               # random: number of configurations
//         stops: 20                # sweep: stops per joint
//         step: 2                  # sweep: deg between stops
//         start: [0, 0, 0, 0, 0, 0]   # sweep: calibration configuration, deg (default zeros)
//         order: [6, 5, 4, 3, 2, 1]   # sweep: joints in sweep order (default n..1)
//         noise: 10um              # position noise sigma per axis
//         noise_range: 5um         # extra sigma per metre of distance to the instrument
//         orientation: false       # also record the tool orientation
//         orientation_noise: 0     # deg per axis
//         marker: [40, 30, 100]    # mm: the measured point on the flange; replaces the tool position of
//                                  # the nominal and the truth for this dataset (validation scores it too)
//       vary: {noise: [1um, 10um, 100um]}   # optional, one knob swept for sensitivity curves:
//                                  # noise, noise_range (length), poses, stops (count), step, arc (deg;
//                                  # arc sets step = arc / (stops - 1))
//     - name: tracker
//       file: ../data/tracker.csv  # measured data (kincal dataset CSV); scored on its test rows
//       split: {test_fraction: 0.3}   # or {every: 3} (every 3rd pose is a test pose) or column (the
//                                  # file's `split` column); a fraction draws new rows each trial
//       iso9283: {tolerance: 0.2mm, angle_tolerance: 0.1, min_cycles: 2}   # optional, measured data:
//                                  # ISO 9283 AP and RP of the test rows' repeated poses: rows whose
//                                  # controller poses lie within the tolerances (length; deg) are visits of
//                                  # one commanded pose (studies/measured_iso9283.h)
//     - name: faro                 # measured data as whitespace tables (tracker and controller exports)
//       tables:                    # row i of every table is pose i, in measurement order
//         joints: ../data/joints.txt           # one column per joint (controller readings)
//         positions: {SMR1: ../data/smr1.txt}  # marker -> x y z table; several markers: one row each
//         units: {length: mm, angle: deg}      # default mm and deg
//       split: {every: 2}          # tables have no split column: give a split
//   estimators:                    # pipelines; the baseline `none` always runs first
//     - least_squares              # a registered name, or a comma-separated pipeline
//     - name: seed                 # label in the results (default: the methods joined by '+')
//       method: geometric,ratio_regression
//       options: {geometric: {}, ratio_regression: {}}   # one method: its options, or keyed by method
//       datasets: [sweep]          # optional: only these datasets (default: all)
//   compensators:                  # the baseline `none` always runs first
//     - jacobian
//     - {name: pd, method: analytic_derivative, options: {}}
//   validation:                    # targets, on simulated datasets (measured data: its test rows)
//     - {name: seed10, random_targets: 10}
//     - name: wide
//       random_targets: 1000
//       orientation: true          # 6-D targets (default); false: position only
//       joint_limits: [[-90, 90], [-60, 60], [-90, 90], [-90, 90], [-90, 90], [-90, 90]]   # deg; where
//                                  # the commanded targets are drawn (default: the nominal limits)
//     - name: iso
//       iso9283:                   # the ISO 9283 cube, poses P1..P5, pose accuracy AP and repeatability RP
//         side: 200mm              # cube edge (default 200 mm)
//         center_configuration: [0, 30, 30, 0, 45, 0]   # deg: cube centre and tool orientation (default:
//                                  # the most dexterous of a deterministic sample of poses that fits the cube)
//         cycles: 30               # ISO: 30
//         joint_noise: 0.001       # deg, sigma of the arm's joint repeatability per cycle
//         measurement_noise: 0     # length, sigma per axis of the instrument
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "robot/robot.h"
#include "robot/simulator.h"
#include "framework/units.h"

namespace kincal {

// Which registries a study draws its methods from: the library's by default; tests add test doubles.
struct MethodRegistries {
  const EstimatorRegistry* estimators = &Estimators();
  const CompensatorRegistry* compensators = &Compensators();
};

struct RobotSpec {
  std::string source;  // the path as written in the study file, or "inline"
  Robot robot;
};

// A knob a dataset sweeps for sensitivity curves.
struct KnobSweep {
  std::string knob;                // noise, noise_range, poses, stops, step, arc
  std::vector<double> values;      // SI (m, m/m, count, rad)
  std::vector<std::string> texts;  // as written in the study file
};

// A measured dataset's `iso9283:` map (keys and requirements: Table(), studies/study_options.cc).
struct MeasuredIso9283Spec {
  double tolerance = 0.2e-3;                    // m: controller poses this close are one commanded pose
  double angle_tolerance = 0.1 * M_PI / 180.0;  // rad
  int min_cycles = 2;                           // visits that make a pose repeated
  static const OptionTable<MeasuredIso9283Spec>& Table();
  bool IsValid(std::string* why) const { return Table().Validate(*this, why); }
};

struct DatasetSpec {
  enum class Split { kColumn, kFraction, kEvery };
  std::string name;
  bool simulated = true;
  SimulatorOptions simulator;             // simulated; its seed is set per trial
  std::optional<Eigen::Vector3d> marker;  // m, tool position override
  std::optional<KnobSweep> vary;
  std::string file;  // measured: resolved path (CSV dataset, or the joints table)
  std::string file_as_written;
  // Measured from tables (`tables:`): `file` is the joints table; one position table per marker.
  bool tables = false;
  std::vector<std::pair<std::string, std::string>> position_tables;  // marker -> resolved path
  std::string sequence_table;  // resolved path of the unfiltered joint readings, "" if none (pose_tables.h)
  Unit table_length_unit = {"mm", 1e-3};
  Unit table_angle_unit = {"deg", M_PI / 180.0};
  Split split = Split::kColumn;
  double test_fraction = 0.0;
  int every = 0;
  // Measured data: ISO 9283 of the test rows' repeated poses (studies/measured_iso9283.h), validation
  // "iso9283" of compensator "-".
  bool iso9283 = false;
  MeasuredIso9283Spec iso;
  std::string summary;  // one line for the report
};

struct PipelineSpec {
  std::string name;
  std::vector<std::string> methods;
  std::vector<std::string> options_yaml;  // per method, YAML text ("" = defaults)
  std::vector<std::string> datasets;      // empty = all
  bool RunsOn(const std::string& dataset) const;
};

struct CompensatorSpec {
  std::string name;
  std::string method;
  std::string options_yaml;
};

// A validation set's `iso9283:` map (keys and requirements: Table(), studies/study_options.cc).
struct Iso9283Spec {
  double side = 0.2;                     // m
  Eigen::VectorXd center_configuration;  // rad; empty = searched
  int cycles = 30;
  double joint_noise = 0.001 * M_PI / 180.0;  // rad
  double measurement_noise = 0.0;             // m
  static const OptionTable<Iso9283Spec>& Table();
  bool IsValid(std::string* why) const { return Table().Validate(*this, why); }
};

struct ValidationSpec {
  enum class Kind { kRandom, kIso9283 };
  std::string name;
  Kind kind = Kind::kRandom;
  int count = 0;  // random targets
  bool orientation = true;
  std::vector<std::pair<double, double>> joint_limits;  // rad; empty = the nominal robot's
  Iso9283Spec iso;
  std::string summary;
  // The keys `random_targets` (count) and `orientation` (studies/study_options.cc); the parser reads the
  // name, the joint ranges and the cube.
  static const OptionTable<ValidationSpec>& Table();
};

struct Study {
  std::string name;
  std::string description;
  std::string source;      // the study file, for messages
  uint64_t text_hash = 0;  // HashLabel of the study file's text (journal fingerprints)
  uint64_t seed = 1;
  int trials = 1;
  int threads = 0;
  RobotSpec nominal;
  std::optional<RobotSpec> truth;
  std::vector<DatasetSpec> datasets;
  std::vector<PipelineSpec> pipelines;        // pipelines[0] is the baseline `none`
  std::vector<CompensatorSpec> compensators;  // compensators[0] is the baseline `none`
  std::vector<ValidationSpec> validation;
};

// Parses a study. Throws std::invalid_argument "file:line:col: key: what" on any problem, including
// unknown methods and invalid method options (each is created once here to check).
Study ParseStudy(const std::string& text, const std::string& source_path,
                 const MethodRegistries& registries = MethodRegistries());
Study ReadStudyFile(const std::string& path, const MethodRegistries& registries = MethodRegistries());

// ---- The plan: what runs, in a fixed order that sharding and merging rely on ---------------------------

// One dataset as simulated with one value of its swept knob (or the dataset itself when it sweeps none).
struct DatasetVariant {
  int dataset = 0;             // index in Study::datasets
  int variant = 0;             // index in the knob's values, 0 without a sweep
  std::string knob;            // "" or the knob with its display unit: noise_um, poses, step_deg, ...
  double knob_value = NAN;     // in the display unit
  std::string label;           // "sweep" or "sweep[noise=10um]"
  SimulatorOptions simulator;  // with the knob applied
};
std::vector<DatasetVariant> Variants(const Study& study);

// The unit of parallel work and of sharding: one pipeline identified on one trial of one dataset
// variant, then every compensator and validation set on the result.
struct WorkItem {
  int index = 0;
  int variant = 0;  // index in Variants()
  int trial = 0;
  int pipeline = 0;
};
// Order: dataset, variant, trial, pipeline.
std::vector<WorkItem> WorkItems(const Study& study, const std::vector<DatasetVariant>& variants);

// Seeds of a trial's random streams: they depend on (study seed, dataset, variant, trial) only, never on
// scheduling, sharding or the pipeline, so every method sees the same data (common random numbers).
uint64_t DatasetSeed(const Study& study, const DatasetVariant& variant, int trial);
uint64_t ValidationSeed(const Study& study, const ValidationSpec& validation);
// FNV-1a, for labels in seeds (std::hash differs between standard libraries).
uint64_t HashLabel(const std::string& text);

// What was run, for study.json: everything the report needs that the result tables do not hold.
// Deterministic (no paths resolved against the working folder, no times).
nlohmann::json StudyManifest(const Study& study, const std::vector<DatasetVariant>& variants, int num_items);

}  // namespace kincal
