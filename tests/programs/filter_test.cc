// kincal filter's library: for each format, a program of 120 targets for its arm (RAPID: IRB 120; KRL:
// KUKA KR 6 R900; URScript: UR10; CSV: IRB 120) filtered for an identified arm whose base is where a
// tracker sees it. The filtered targets, given to the controller's inverse kinematics on the branch
// their configuration fields name, put the identified arm on the original targets; everything but the
// target numbers is unchanged; with identified = nominal no byte changes.
#include <stdexcept>

#include <gtest/gtest.h>

#include "compensators/compensator.h"
#include "programs/filter.h"
#include "tests/programs/programs_fixture.h"

namespace kincal {
namespace {

struct Case {
  std::string format, robot;
};

std::string Program(const std::string& format, const Robot& controller, const std::vector<Eigen::VectorXd>& qs) {
  if (format == "rapid") return testing::RapidModule(controller, qs, 5);
  if (format == "krl") return testing::KrlDataList(controller, qs, 5);
  if (format == "urscript") return testing::UrScript(controller, qs, 5);
  return testing::CsvTargets(controller, qs);
}

// The text with every target number replaced by '#'.
std::string Skeleton(const std::string& text, const std::vector<ProgramTarget>& targets) {
  std::vector<NumberSpan> spans;
  std::vector<double> values;
  for (const ProgramTarget& t : targets) {
    for (NumberSpan s : t.numbers) {
      s.integer = false;
      spans.push_back(s);
      values.push_back(NAN);
    }
  }
  std::string out = ReplaceNumbers(text, spans, values, 0.0);  // NaN: every span rewritten as "nan"
  return out;
}

class FilterRoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(FilterRoundTrip, FilteredTargetsPutTheIdentifiedArmOnTheOriginals) {
  const Case& c = GetParam();
  const Robot nominal = testing::LoadExampleRobot(c.robot);
  const Robot identified = testing::Identified(nominal, 7);
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat(c.format);
  const ProgramFilter filter(nominal, identified, Compensators().Create("analytic_derivative", YAML::Load("{}")), {},
                             format->convention());
  const Robot& controller = filter.controller();
  const std::vector<Eigen::VectorXd> qs = testing::Configurations(controller, 120, 3);
  const std::string text = Program(c.format, controller, qs);
  const FilteredProgram out = filter.Filter(*format, text, "in." + c.format);
  for (const std::string& line : out.report.not_reached) ADD_FAILURE() << line;
  EXPECT_EQ(out.report.filtered, 120);

  const std::vector<ProgramTarget> before = format->Read(text, "in");
  const std::vector<ProgramTarget> after = format->Read(out.text, "out");
  ASSERT_EQ(before.size(), 120u);
  ASSERT_EQ(after.size(), before.size());
  EXPECT_EQ(Skeleton(out.text, after), Skeleton(text, before));
  EXPECT_NE(out.text, text);

  const NominalInverseKinematics ik(controller);
  const ConfigurationRules rules(format->convention(), controller);
  const Eigen::Isometry3d T_meas_base = controller.model().base();
  Eigen::VectorXd previous;
  int changed_fields = 0;
  for (size_t i = 0; i < before.size(); ++i) {
    ASSERT_EQ(after[i].kind, before[i].kind);
    ASSERT_EQ(after[i].line, before[i].line);
    Eigen::VectorXd q;
    Eigen::Isometry3d T_original;
    if (before[i].kind == ProgramTarget::Kind::kPose) {
      const Eigen::Isometry3d T_filtered = T_meas_base * after[i].T_frame_tool;
      T_original = T_meas_base * before[i].T_frame_tool;
      if (after[i].seed.size()) {  // CSV: the seeds are the controller's solution of the filtered pose
        q = after[i].seed;
        EXPECT_LE(PoseError(controller.model().ForwardKinematics(q), T_filtered).head<3>().norm(), 1e-9) << i;
      } else {
        const ConfigurationRules::Solution s = rules.Solve(ik, T_filtered, after[i].configuration, previous);
        ASSERT_TRUE(s.found) << "target " << i << " line " << after[i].line;
        q = s.q;
      }
      changed_fields += after[i].configuration != before[i].configuration;
    } else {
      q = after[i].q;
      T_original = controller.model().ForwardKinematics(before[i].q);
    }
    const Vector6d e = PoseError(identified.model().ForwardKinematics(q), T_original);
    EXPECT_LE(e.head<3>().norm(), 1e-9) << "target " << i << " line " << after[i].line;  // 1e-6 mm
    EXPECT_LE(e.tail<3>().norm(), 1e-8) << "target " << i << " line " << after[i].line;
    previous = q;
  }
  RecordProperty("configuration_fields_changed", changed_fields);
}

TEST_P(FilterRoundTrip, WithoutCalibrationNoByteChanges) {
  const Case& c = GetParam();
  const Robot nominal = testing::LoadExampleRobot(c.robot);
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat(c.format);
  const ProgramFilter filter(nominal, nominal, Compensators().Create("analytic_derivative", YAML::Load("{}")), {},
                             format->convention());
  const std::string text = Program(c.format, filter.controller(), testing::Configurations(nominal, 120, 4));
  const FilteredProgram out = filter.Filter(*format, text, "in");
  EXPECT_TRUE(out.report.not_reached.empty());
  EXPECT_EQ(out.report.filtered, 120);
  EXPECT_EQ(out.text, text);
}

std::string Name(const ::testing::TestParamInfo<Case>& info) { return info.param.format; }

INSTANTIATE_TEST_SUITE_P(Formats, FilterRoundTrip,
                         ::testing::Values(Case{"rapid", "irb120_mdh.yaml"}, Case{"krl", "kuka_kr6_r900.yaml"},
                                           Case{"urscript", "ur10_dh.yaml"}, Case{"csv", "irb120_mdh.yaml"}),
                         Name);

// A confdata field is a quadrant number: one beyond what an int holds is refused at its column (its
// conversion to int would overflow).
TEST(RapidReader, AConfdataFieldBeyondAnIntIsRefusedAtItsColumn) {
  const std::string text =
      "MODULE M\n"
      "  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,-1.6E+127,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];\n"
      "ENDMODULE\n";
  try {
    MakeProgramFormat("rapid")->Read(text, "m.mod");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("m.mod:2:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("confdata fields are integers"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace kincal
