#include "studies/study_options.h"

#include <cmath>

#include "studies/study.h"

namespace kincal {
namespace {

// A list of angles: degrees in files, radians in `v`.
std::vector<double> Degrees(const Eigen::VectorXd& v) {
  std::vector<double> deg;
  for (Eigen::Index i = 0; i < v.size(); ++i) deg.push_back(v[i] * 180.0 / M_PI);
  return deg;
}
Eigen::VectorXd Radians(const std::vector<double>& deg) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(deg.size()));
  for (size_t i = 0; i < deg.size(); ++i) v[static_cast<Eigen::Index>(i)] = deg[i] * M_PI / 180.0;
  return v;
}

}  // namespace

const OptionTable<StudySettings>& StudySettings::Table() {
  using O = StudySettings;
  static const OptionTable<O> table =
      OptionTable<O>("study")
          .Add<double>(
              "seed", [](const O& o) { return static_cast<double>(o.seed); },
              [](O* o, const double& seed) {
                // Integers up to 9e15 are exact in a double, as YAML numbers are read.
                if (seed != std::floor(seed) || seed < 0 || seed > 9.0e15) {
                  throw std::invalid_argument("expected an integer >= 0");
                }
                o->seed = static_cast<uint64_t>(seed);
              },
              "every random stream derives from it")
          .Add("trials", &O::trials, "Monte Carlo trials (new noise, new random poses each)", AtLeast(1))
          .Add("threads", &O::threads, "worker threads, 0: every core (`--threads` overrides)", AtLeast(0));
  return table;
}

const OptionTable<SimulateOptions>& SimulateOptions::Table() {
  using O = SimulateOptions;
  const Requirement<std::vector<double>> xyz = [](const std::vector<double>& v) {
    for (double x : v) {
      if (!std::isfinite(x)) return std::string("must be finite");
    }
    return v.empty() || v.size() == 3 ? std::string() : std::string("expected [x, y, z] in mm");
  };
  static const OptionTable<O> table =
      OptionTable<O>("simulate")
          .Include(SimulatorOptions::Table(), &O::simulator)
          .Add("marker", &O::marker,
               "mm, [x, y, z]: the measured point on the flange; replaces the tool position of the nominal and "
               "the truth for this dataset (validation scores it too)",
               xyz);
  return table;
}

const OptionTable<MeasuredIso9283Spec>& MeasuredIso9283Spec::Table() {
  using O = MeasuredIso9283Spec;
  static const OptionTable<O> table =
      OptionTable<O>("iso9283")
          .Add("tolerance", OptionUnit::kLengthMm, &O::tolerance,
               "test rows whose controller poses lie this close are visits of one commanded pose", Positive())
          .Add("angle_tolerance", OptionUnit::kAngleDeg, &O::angle_tolerance, "the same, for the orientation",
               Positive())
          .Add("min_cycles", &O::min_cycles, "visits that make a pose repeated", AtLeast(2));
  return table;
}

const OptionTable<Iso9283Spec>& Iso9283Spec::Table() {
  using O = Iso9283Spec;
  static const OptionTable<O> table =
      OptionTable<O>("iso9283")
          .Add("side", OptionUnit::kLengthMm, &O::side, "the cube's edge", Positive())
          .Add<std::vector<double>>(
              "center_configuration", [](const O& o) { return Degrees(o.center_configuration); },
              [](O* o, const std::vector<double>& deg) { o->center_configuration = Radians(deg); },
              "deg, one per joint: the cube's centre and the tool's orientation (default: the most dexterous of a "
              "deterministic sample of poses that fits the cube)")
          .Add("cycles", &O::cycles, "cycles through P1..P5 (ISO 9283: 30)", AtLeast(2))
          .Add("joint_noise", OptionUnit::kAngleDeg, &O::joint_noise,
               "sigma of the arm's joint repeatability per cycle", NonNegative())
          .Add("measurement_noise", OptionUnit::kLengthMm, &O::measurement_noise, "sigma per axis of the instrument",
               NonNegative());
  return table;
}

const OptionTable<ValidationSpec>& ValidationSpec::Table() {
  using O = ValidationSpec;
  static const OptionTable<O> table =
      OptionTable<O>("validation")
          .Add("random_targets", &O::count, "random targets within the joint limits (or `joint_limits`)", AtLeast(1))
          .Add("orientation", &O::orientation, "6-D targets; false: positions only");
  return table;
}

std::vector<std::pair<std::string, std::vector<OptionDoc>>> StudyOptionDocs() {
  return {{"(top level)", StudySettings::Table().Docs()},
          {"datasets[].simulate", SimulateOptions::Table().Docs()},
          {"datasets[].iso9283", MeasuredIso9283Spec::Table().Docs()},
          {"validation[]", ValidationSpec::Table().Docs()},
          {"validation[].iso9283", Iso9283Spec::Table().Docs()}};
}

}  // namespace kincal
