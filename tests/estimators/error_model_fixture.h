#pragma once
// Shared fixture of the error-model estimators (least_squares, ceres, nlopt, ipopt): simulated data of
// the seed's arm with a known truth (examples/robots/seed_identified.yaml) seen from a tracker frame
// metres away, and the checks every estimator must pass. An estimator joins by adding its name to
// kErrorModelEstimators; names not registered are skipped.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal::testing {

inline const std::vector<std::string> kErrorModelEstimators = {"least_squares", "ceres", "nlopt", "ipopt"};

// Options each estimator runs the shared checks with (tight tolerances: the checks go to rounding level).
inline YAML::Node FixtureOptions(const std::string& name) {
  YAML::Node node(YAML::NodeType::Map);
  if (name == "least_squares") node["parameter_tolerance"] = 1e-12;
  return node;
}

// T_tracker_base of the simulations: the instrument stands metres away, arbitrarily turned.
inline Eigen::Isometry3d TrackerBase() {
  return PoseFromXyzRpy(Eigen::Vector3d(1.8, -0.6, 0.4), Eigen::Vector3d(0.3, -0.2, 2.0));
}

struct SimulatedCase {
  Robot nominal;  // the start and the controller: Table 1, nominal ratios, identity base
  Robot truth;    // Table 2, identified ratios, TrackerBase()
  Dataset data;
};

// `poses` random poses within the joint limits, position noise `noise` (m per axis), encoder counts.
inline SimulatedCase RandomPoseCase(int poses, double noise, uint64_t seed) {
  SimulatedCase c;
  c.nominal = SeedNominal();
  c.truth = SeedTruth();
  c.truth.model().SetBase(TrackerBase());
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = poses;
  so.noise_sigma = noise;
  so.seed = seed;
  c.data = Simulate(c.nominal, c.truth, so);
  return c;
}

// The seed's own protocol (METHOD.md 2): joints swept one at a time, 20 stops 2 deg apart.
inline SimulatedCase SweepCase(double noise, uint64_t seed) {
  SimulatedCase c = RandomPoseCase(1, noise, seed);
  SimulatorOptions so;
  so.protocol = "sweep";
  so.noise_sigma = noise;
  so.seed = seed;
  so.start = Eigen::VectorXd::Zero(6);
  c.data = Simulate(c.nominal, c.truth, so);
  return c;
}

// Position errors of `identified` on `poses` fresh random poses of the truth, noise-free.
inline ErrorStats HeldOutErrors(const SimulatedCase& c, const Robot& identified, int poses, uint64_t seed) {
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = poses;
  so.seed = seed;
  const Dataset test = Simulate(c.nominal, c.truth, so);
  return EvaluatePredictions(c.nominal, identified, test).position_stats;
}

// The truth's value of a report parameter (model parameters and ratios).
inline double TruthValue(const Robot& truth, const std::string& name) {
  if (name.rfind("ratio_", 0) == 0) return truth.drives->ratio[std::stoi(name.substr(6)) - 1];
  return truth.model().Parameter(name);
}

// Characteristic size of a report parameter, to express errors relatively: 1 m, 1 rad, or the ratio.
inline double ParameterSize(const ParameterEstimate& p) { return p.unit.empty() ? std::abs(p.nominal) : 1.0; }

inline Robot RunEstimator(const std::string& name, const Robot& nominal, const Dataset& data, EstimationReport* report,
                          const YAML::Node& options) {
  Robot identified;
  *report = Estimators().Create(name, options)->Estimate(nominal, data, &identified);
  return identified;
}

class ErrorModelEstimatorTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { ASSERT_TRUE(Estimators().IsRegistered(GetParam())) << GetParam() << " is not registered"; }
  Robot Run(const Dataset& data, const Robot& nominal, EstimationReport* report) const {
    return RunEstimator(GetParam(), nominal, data, report, FixtureOptions(GetParam()));
  }
};

}  // namespace kincal::testing
