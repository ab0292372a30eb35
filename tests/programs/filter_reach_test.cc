// kincal filter on targets the real arm reaches and the nominal controller may not: 200 random IRB 120
// robtargets with ABB's confdata, taught on the identified arm (its forward kinematics at random joints,
// the fields of those joints). Near the stretched elbow some lie outside the nominal arm's reach; each
// must still be filtered, and the filtered targets, solved by the nominal controller on the branch they
// name, must put the identified arm on the originals.
#include <gtest/gtest.h>

#include "compensators/compensator.h"
#include "programs/filter.h"
#include "tests/programs/programs_fixture.h"

namespace kincal {
namespace {

using testing::Fmt;

// Random joints inside the limits, every joint 2 deg or more from the quadrant edges (so that the written
// fields are the joints' own), written as MoveL robtargets of the identified arm in the controller's base.
std::string TaughtOnTheRealArm(const Robot& controller, const Robot& identified, int count, uint64_t seed) {
  const ConfigurationRules rules(ConfigurationConvention::kAbb, controller);
  Rng rng(seed);
  const double margin = 2 * M_PI / 180;
  std::string body;
  for (int n = 0; n < count;) {
    Eigen::VectorXd q(6);
    bool ok = true;
    for (int j = 0; j < 6; ++j) {
      const auto [low, high] = identified.Limit(j);
      q[j] = rng.Uniform(low + margin, high - margin);
      ok = ok && std::abs(std::remainder(q[j], M_PI / 2)) > margin;
    }
    if (!ok) continue;
    const Eigen::Isometry3d T = controller.model().base().inverse() * identified.model().ForwardKinematics(q);
    const Eigen::Quaterniond quat(T.linear());
    const std::vector<int> c = rules.Of(q);
    body += "    MoveL [[" + Fmt("%.6f", T.translation().x() * 1e3) + "," + Fmt("%.6f", T.translation().y() * 1e3) +
            "," + Fmt("%.6f", T.translation().z() * 1e3) + "],[" + Fmt("%.12f", quat.w()) + "," +
            Fmt("%.12f", quat.x()) + "," + Fmt("%.12f", quat.y()) + "," + Fmt("%.12f", quat.z()) + "],[" +
            std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "," +
            std::to_string(c[3]) + "],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], v200, fine, tool0;\n";
    ++n;
  }
  return "MODULE Taught\n  PROC main()\n" + body + "  ENDPROC\nENDMODULE\n";
}

class FilterReach : public ::testing::TestWithParam<uint64_t> {};

TEST_P(FilterReach, EveryTargetTheRealArmReachesIsFiltered) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot identified = testing::Identified(nominal, GetParam());
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat("rapid");
  const ProgramFilter filter(nominal, identified, Compensators().Create("analytic_derivative", YAML::Load("{}")), {},
                             format->convention());
  const Robot& controller = filter.controller();
  const std::string text = TaughtOnTheRealArm(controller, identified, 200, 100 + GetParam());
  const FilteredProgram out = filter.Filter(*format, text, "taught.mod");
  for (const std::string& line : out.report.not_reached) ADD_FAILURE() << line;
  EXPECT_EQ(out.report.filtered, 200);

  const std::vector<ProgramTarget> before = format->Read(text, "in"), after = format->Read(out.text, "out");
  ASSERT_EQ(after.size(), before.size());
  const NominalInverseKinematics ik(controller);
  const ConfigurationRules rules(format->convention(), controller);
  const Eigen::Isometry3d T_meas_base = controller.model().base();
  int outside_nominal_reach = 0;
  Eigen::VectorXd previous;
  for (size_t i = 0; i < before.size(); ++i) {
    const Eigen::Isometry3d T_original = T_meas_base * before[i].T_frame_tool;
    outside_nominal_reach += !rules.Solve(ik, T_original, before[i].configuration, previous).found;
    const ConfigurationRules::Solution s =
        rules.Solve(ik, T_meas_base * after[i].T_frame_tool, after[i].configuration, previous);
    ASSERT_TRUE(s.found) << "target " << i << " line " << after[i].line;
    EXPECT_EQ(after[i].configuration, before[i].configuration) << "target " << i;
    const Vector6d e = PoseError(identified.model().ForwardKinematics(s.q), T_original);
    EXPECT_LE(e.head<3>().norm(), 1e-9) << "target " << i << " line " << after[i].line;  // 1e-6 mm
    EXPECT_LE(e.tail<3>().norm(), 1e-8) << "target " << i << " line " << after[i].line;
    previous = s.q;
  }
  // The case this test is for: targets the nominal controller does not reach on their branch.
  EXPECT_GT(outside_nominal_reach, 0);
  RecordProperty("outside_nominal_reach", outside_nominal_reach);
  std::printf("%d of %zu targets outside the nominal controller's reach on their branch\n", outside_nominal_reach,
              before.size());
}

// Three identified arms (and programs): 2, 8 and 13 of their 200 targets are outside the nominal reach.
INSTANTIATE_TEST_SUITE_P(Arms, FilterReach, ::testing::Values(3, 4, 5));

// A target that neither arm reaches stays as written, and the reason says the real arm has no solution.
TEST(FilterReachOut, KeptAsWrittenWhereTheRealArmHasNoSolution) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot identified = testing::Identified(nominal, 3);
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat("rapid");
  const ProgramFilter filter(nominal, identified, Compensators().Create("analytic_derivative", YAML::Load("{}")), {},
                             format->convention());
  const std::string text =
      "MODULE Far\n  PROC main()\n    MoveL [[900,0,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], "
      "v200, fine, tool0;\n  ENDPROC\nENDMODULE\n";
  const FilteredProgram out = filter.Filter(*format, text, "far.mod");
  ASSERT_EQ(out.report.not_reached.size(), 1u);
  EXPECT_EQ(out.report.not_reached[0],
            "far.mod:3: the real arm has no solution on the branch its configuration names (nor has the controller)");
  EXPECT_EQ(out.text, text);
}

}  // namespace
}  // namespace kincal
