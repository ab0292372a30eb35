#pragma once
// Shared fixture of the error-model estimators (least_squares, ceres, nlopt, ipopt): simulated data of
// the seed's arm with a known truth (examples/robots/seed_identified.yaml) seen from a tracker frame
// metres away, and the checks every estimator must pass. An estimator joins by adding its name to
// kErrorModelEstimators; names not registered are skipped.
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "testing/estimator_conformance.h"
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

// The seed arm seen from three tracker stations (rows in pairs: session 0, 1, 2, 0, ...), two reflectors,
// orientations measured.
inline SimulatedCase SessionCase(int poses, double noise, uint64_t seed) {
  SimulatedCase c = RandomPoseCase(1, 0.0, seed);
  c.truth.markers = {{"A", Eigen::Vector3d(0.04, 0.03, 0.10)}, {"B", Eigen::Vector3d(-0.06, 0.02, 0.09)}};
  c.truth.session_bases[1] = PoseFromXyzRpy(Eigen::Vector3d(-1.5, 1.1, 0.2), Eigen::Vector3d(-0.1, 0.15, -2.4));
  c.truth.session_bases[2] = PoseFromXyzRpy(Eigen::Vector3d(0.3, 2.2, -0.3), Eigen::Vector3d(0.05, 0.1, 0.7));
  c.nominal.markers = {{"A", Eigen::Vector3d(0.043, 0.028, 0.105)}, {"B", Eigen::Vector3d(-0.058, 0.024, 0.087)}};
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = poses;
  so.noise_sigma = noise;
  so.orientation = true;
  so.seed = seed;
  c.data = Simulate(c.nominal, c.truth, so);
  for (size_t i = 0; i < c.data.rows.size(); ++i) {
    Measurement& m = c.data.rows[i];
    m.session = static_cast<int>(i / 2) % 3;
    if (m.session != 0) {
      // The tracker stood elsewhere: re-measure from its frame.
      const Eigen::Isometry3d T_k_0 = c.truth.session_bases.at(m.session) * c.truth.model().base().inverse();
      m.p = T_k_0 * m.p;
      m.orientation = Eigen::Quaterniond(T_k_0.linear() * m.orientation->toRotationMatrix());
    }
  }
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
  return testing::HeldOutErrors(c.nominal, c.truth, identified, poses, seed);
}

// The truth's value of a report parameter (model parameters and ratios).
inline double TruthValue(const Robot& truth, const std::string& name) {
  if (name.rfind("ratio_", 0) == 0) return truth.drives->ratio[std::stoi(name.substr(6)) - 1];
  return truth.model().Parameter(name);
}

// Characteristic size of a report parameter, to express errors relatively: 1 m, 1 rad, or the ratio.
inline double ParameterSize(const ParameterEstimate& p) { return p.unit.empty() ? std::abs(p.nominal) : 1.0; }

// A report's parameters by name.
inline std::map<std::string, const ParameterEstimate*> ByName(const EstimationReport& report) {
  std::map<std::string, const ParameterEstimate*> out;
  for (const auto& p : report.parameters) out[p.name] = &p;
  return out;
}

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
