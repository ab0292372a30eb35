// The example plugin's own test, built against an installed kincal and its conformance kits
// (testing/estimator_conformance.h, testing/compensator_conformance.h): the plugin loaded as kincal loads
// it (framework/plugin.h), its estimator recovers a simulated truth and never ends worse than it starts,
// its compensator reaches targets the identified arm reaches, on the solution of the built-in `jacobian`
// wherever both take the same branch.
//   KINCAL_EXAMPLE_PLUGIN: the plugin's file; KINCAL_EXAMPLE_ROBOTS: kincal's examples/robots folder.
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "framework/plugin.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "testing/compensator_conformance.h"
#include "testing/estimator_conformance.h"

namespace {

// The plugin's registrations, in registries of this test's own.
struct Loaded {
  kincal::Registry<kincal::Estimator> estimators;
  kincal::Registry<kincal::Compensator> compensators;
  Loaded() {
    kincal::RegistryRegistrar registrar(&estimators, &compensators);
    kincal::LoadPlugin(KINCAL_EXAMPLE_PLUGIN, registrar);
  }
};
const Loaded& Plugin() {
  static const Loaded loaded;
  return loaded;
}
kincal::Robot ExampleRobot(const std::string& file) {
  return kincal::ReadRobotFile(std::string(KINCAL_EXAMPLE_ROBOTS) + "/" + file);
}

// Joints within +-60 deg where the identified arm's Jacobian is well conditioned (sigma_min / sigma_max
// >= 0.01, position rows in units of 0.5 m, as kincal's own compensator suite draws its targets): undamped
// Newton steps are not made for singular configurations.
Eigen::VectorXd WellConditionedJoints(const kincal::Robot& robot, kincal::Rng* rng) {
  for (;;) {
    Eigen::VectorXd q(robot.dof());
    for (int j = 0; j < q.size(); ++j) q[j] = rng->Uniform(-60, 60) * M_PI / 180;
    Eigen::MatrixXd J = robot.model().JointJacobian(q);
    J.topRows(3) /= 0.5;
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
    if (s[s.size() - 1] >= 0.01 * s[0]) return q;
  }
}

TEST(ExamplePlugin, EstimatorRecoversASimulatedTruth) {
  const auto estimator = Plugin().estimators.Create("example_least_squares");
  // Noise-free data of the seed's arm: the truth to well under a micrometre.
  EXPECT_TRUE(kincal::testing::RecoversSimulatedTruth(*estimator, ExampleRobot("seed_nominal.yaml"),
                                                      ExampleRobot("seed_identified.yaml"), 1e-9));
}

TEST(ExamplePlugin, CompensatorReachesReachableTargets) {
  const kincal::Robot nominal = ExampleRobot("seed_nominal.yaml");
  const kincal::Robot identified = ExampleRobot("seed_identified.yaml");
  const auto newton = Plugin().compensators.Create("example_newton");
  const auto jacobian = kincal::Compensators().Create("jacobian");
  newton->Prepare(nominal, identified);
  jacobian->Prepare(nominal, identified);
  kincal::Rng rng(11);
  int same = 0;
  for (int k = 0; k < 10; ++k) {
    const Eigen::VectorXd q = WellConditionedJoints(identified, &rng);
    const kincal::CompensationTarget target = kincal::testing::ReachableTarget(identified, q);
    EXPECT_TRUE(kincal::testing::ReachesTarget(*newton, identified, target, 1e-12, 1e-12)) << "target " << k;
    // The seed arm has several solutions per pose and jacobian's branch restarts may take another than
    // Newton's from the same seed: where they agree within a degree, they are the same solution.
    const double d = (newton->Compensate(target).q_actual - jacobian->Compensate(target).q_actual).cwiseAbs().maxCoeff();
    if (d < M_PI / 180) {
      EXPECT_LT(d, 1e-8) << "target " << k;
      ++same;
    }
  }
  EXPECT_GE(same, 7);
}

}  // namespace
