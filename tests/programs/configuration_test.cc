// Configuration fields against the manufacturers' documented values: ABB's confdata at the zero position
// is [0,0,0,0], quadrants are floor(angle / 90 deg), axis 5 < 0 sets cfx's bit 0 and a lower arm leaning
// back past the vertical far enough puts the wrist centre behind axis 1 (bit 2); KUKA's HOME
// {0,-90,90,0,0,0} has S 'B010' and T 'B000010', a negative A5 sets S bit 2 and T bit 4, and a target
// behind A1 (overhead) S bit 0.
#include <gtest/gtest.h>

#include <algorithm>

#include "framework/math.h"
#include "framework/random.h"
#include "programs/configuration.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

Eigen::VectorXd Deg(std::initializer_list<double> values) {
  Eigen::VectorXd q(values.size());
  int k = 0;
  for (double v : values) q[k++] = v * M_PI / 180;
  return q;
}

TEST(Configuration, AbbConfdata) {
  const Robot irb120 = testing::LoadExampleRobot("irb120_mdh.yaml");
  const ConfigurationRules abb(ConfigurationConvention::kAbb, irb120);
  EXPECT_EQ(abb.Of(Deg({0, 0, 0, 0, 0, 0})), (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(abb.Of(Deg({100, 10, 10, -10, 30, 200})), (std::vector<int>{1, -1, 2, 0}));
  EXPECT_EQ(abb.Of(Deg({-10, 10, 10, 95, -30, -95})), (std::vector<int>{-1, 1, -2, 1}));
  EXPECT_EQ(abb.Of(Deg({0, -100, 0, 0, 30, 0}))[3] & 4, 4);  // leaning back: wrist behind axis 1
  // Elbow bent back (axis 3 at its lower limit region) flips the lower-arm bit against the zero position.
  EXPECT_NE(abb.Of(Deg({0, 0, -100, 0, 30, 0}))[3] & 2, abb.Of(Deg({0, 0, 30, 0, 30, 0}))[3] & 2);
}

TEST(Configuration, KukaStatusAndTurn) {
  const Robot kr6 = testing::LoadExampleRobot("kuka_kr6_r900.yaml");
  const ConfigurationRules kuka(ConfigurationConvention::kKuka, kr6);
  EXPECT_EQ(kuka.Of(Deg({0, -90, 90, 0, 0, 0})), (std::vector<int>{2, 2}));
  EXPECT_EQ(kuka.Of(Deg({0, -90, 90, 0, -30, 0})), (std::vector<int>{6, 2 + 16}));
  EXPECT_EQ(kuka.Of(Deg({-20, -90, 90, -10, 30, -200})), (std::vector<int>{2, 1 + 2 + 8 + 32}));
  EXPECT_EQ(kuka.Of(Deg({0, -90, -60, 0, 30, 0}))[0], 1);  // forearm up and back: overhead, A3 < phi
}

// The fields are the arm's joints', not the tool's: with a tool offset in every direction (so the tool
// point is off the plane through the wrist centre normal to axis 5) they are the flange's, at random joints
// and at joints next to the stretched elbow, where the lower-arm bit flips.
TEST(Configuration, FieldsDoNotDependOnTheTool) {
  for (const auto& [file, convention] : {std::pair{"irb120_mdh.yaml", ConfigurationConvention::kAbb},
                                         std::pair{"kuka_kr6_r900.yaml", ConfigurationConvention::kKuka}}) {
    const Robot flange = testing::LoadExampleRobot(file);
    Robot tooled = flange;
    tooled.model().SetTool(PoseFromXyzRpy({0.03, -0.04, 0.15}, {0.3, -0.2, 0.1}));
    const ConfigurationRules bare(convention, flange), with_tool(convention, tooled);
    Rng rng(17);
    for (int t = 0; t < 2000; ++t) {
      Eigen::VectorXd q(6);
      for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(flange.Limit(j).first, flange.Limit(j).second);
      EXPECT_EQ(with_tool.Of(q), bare.Of(q)) << file << " q " << q.transpose();
    }
  }
}

// Each named branch is solved back: the eight arm/wrist configurations of one pose are eight different
// field values, and solving on each gives a configuration with those fields.
TEST(Configuration, EveryBranchIsNamedAndSolvedBack) {
  for (const auto& [file, convention] : {std::pair{"irb120_mdh.yaml", ConfigurationConvention::kAbb},
                                         std::pair{"kuka_kr6_r900.yaml", ConfigurationConvention::kKuka}}) {
    const Robot robot = testing::LoadExampleRobot(file);
    const ConfigurationRules rules(convention, robot);
    const NominalInverseKinematics ik(robot);
    const Eigen::Isometry3d T = robot.model().ForwardKinematics(Deg({20, 10, 15, 30, 40, 50}));
    const std::vector<IkSolution> branches = ik.AllBranches(T, Eigen::VectorXd());
    std::vector<std::vector<int>> seen;
    int inside = 0;
    for (const IkSolution& b : branches) {
      if (b.status != IkStatus::kSolved) continue;
      ++inside;
      const std::vector<int> c = rules.Of(b.q);
      EXPECT_EQ(std::count(seen.begin(), seen.end(), c), 0) << file;
      seen.push_back(c);
      const ConfigurationRules::Solution s = rules.Solve(ik, T, c, Eigen::VectorXd());
      ASSERT_TRUE(s.found) << file;
      EXPECT_EQ(rules.Of(s.q), c);
      EXPECT_LE(PoseError(robot.model().ForwardKinematics(s.q), T).norm(), 1e-9);
    }
    EXPECT_GE(inside, 2) << file;
  }
}

}  // namespace
}  // namespace kincal
