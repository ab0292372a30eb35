// `kincal filter` end to end: a RAPID module for an identified IRB 120 with one target out of reach (kept
// as written, reported with its line, counted); malformed programs and what kincal does not filter give
// exit status 2, one line naming file, line and column, and no output file; the work object and tool
// from flags or from a --filter-options file (whose bad values name their line and column).
#include <gtest/gtest.h>

#include <filesystem>

#include "programs/filter.h"
#include "robot/robot_file.h"
#include "tests/programs/programs_fixture.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::TempDir;

struct Files {
  TempDir dir;
  std::string nominal = testing::SourcePath("examples/robots/irb120_mdh.yaml");
  std::string identified = dir.path("identified.yaml");
  Files() { WriteRobotFile(testing::Identified(testing::LoadExampleRobot("irb120_mdh.yaml"), 11), identified); }
  std::string Args(const std::string& program, const std::string& out) const {
    return "filter --nominal " + nominal + " --identified " + identified + " --program " + program + " --out " + out;
  }
};

TEST(FilterCommand, UnreachableTargetsStayAsWrittenAndAreReported) {
  Files f;
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot controller = ControllerRobot(nominal, ReadRobotFile(f.identified));
  std::string text = testing::RapidModule(controller, testing::Configurations(controller, 20, 5), 4);
  const std::string far = "[[5000,0,300],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]";
  text.insert(text.find("  PROC main()"), "  CONST robtarget far:=" + far + ";\n");
  testing::WriteText(f.dir.path("in.mod"), text);
  const auto r = RunKincal(f.Args(f.dir.path("in.mod"), f.dir.path("out.mod")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("20 filtered, 1 kept as written"), std::string::npos) << r.out;
  int line = 1;
  for (size_t i = 0; i < text.find("far:="); ++i) line += text[i] == '\n';
  EXPECT_NE(r.err.find("in.mod:" + std::to_string(line) + ":"), std::string::npos) << r.err;
  const std::string out = testing::ReadText(f.dir.path("out.mod"));
  EXPECT_NE(out.find(far), std::string::npos);
  EXPECT_NE(out, text);
}

// Each bad program: exit 2, one line with path:line:column, no output file.
TEST(FilterCommand, BadProgramsExitTwoWithOneLineAndWriteNothing) {
  Files f;
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"a.mod", "MODULE M\n  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0]];\nENDMODULE\n", "a.mod:2:22"},
      {"b.mod", "MODULE M\n  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9];\nENDMODULE\n",
       "b.mod:2:76"},
      {"c.mod", "MODULE M\n  PROC main()\n    MoveL Offs(p10, 0, 0, 100), v100, z10, tool0;\n", "c.mod:3:11"},
      {"d.mod", "MODULE M\n  CONST robtarget p:=[[1,2,3],[2,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n",
       "d.mod:2:31"},
      {"e.dat", "DEFDAT X\nDECL E6POS P={X 1,Y 2,Z 3,A 0,B 0,C 0,S 2}\nENDDAT\n", "e.dat:2:14"},
      {"f.dat", "DEFDAT X\nDECL E6AXIS J={A1 0,A2 -90,A3 x}\nENDDAT\n", "f.dat:2:31"},
      {"g.script", "def f():\n  movel(p[0.1, 0.2, 0.3, 0, 0])\nend\n", "g.script:2:9"},
      {"h.csv", "x_mm,y_mm,z_mm\n1,2,3\n", "h.csv:1:1"},
  };
  for (const auto& [name, text, where] : cases) {
    testing::WriteText(f.dir.path(name), text);
    const std::string out = f.dir.path(name + ".out");
    const auto r = RunKincal(f.Args(f.dir.path(name), out));
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << name << ": " << r.err;
    EXPECT_NE(r.err.find(where), std::string::npos) << name << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << name;
  }
  const auto r = RunKincal(f.Args(f.dir.path("a.mod"), f.dir.path("x.out")) + " --format gcode");
  EXPECT_EQ(r.exit_code, 2);
  const auto ext = RunKincal(f.Args(f.dir.path("prog.txt"), f.dir.path("y.out")));
  EXPECT_EQ(ext.exit_code, 2);
  EXPECT_NE(ext.err.find(".txt"), std::string::npos) << ext.err;
}

// A work object and a tool given as options: the targets are read in that frame, for that tool.
TEST(FilterCommand, WorkObjectAndToolOptions) {
  Files f;
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  Robot identified = ReadRobotFile(f.identified);
  const Eigen::Isometry3d T_flange_tool = PoseFromXyzRpy({0.01, 0.0, 0.15}, {0.0, 0.3, 0.0});
  identified.model().SetTool(T_flange_tool);
  const Robot controller = ControllerRobot(nominal, identified);
  const Eigen::Isometry3d T_base_wobj = PoseFromXyzRpy({0.3, -0.1, 0.05}, {0.0, 0.0, 0.5});
  const std::vector<Eigen::VectorXd> qs = testing::Configurations(controller, 30, 6);
  testing::WriteText(f.dir.path("w.mod"), testing::RapidModule(controller, qs, 1000, T_base_wobj));
  const auto r =
      RunKincal(f.Args(f.dir.path("w.mod"), f.dir.path("w.out.mod")) +
                " --work-object \"300 -100 50 28.64788975654116 0 0\" --tool \"10 0 150 0 17.188733853924695 0\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto format = MakeProgramFormat("rapid");
  const auto before = format->Read(testing::ReadText(f.dir.path("w.mod")), "w.mod");
  const auto after = format->Read(testing::ReadText(f.dir.path("w.out.mod")), "w.out.mod");
  ASSERT_EQ(after.size(), 30u);
  const NominalInverseKinematics ik(controller);
  const ConfigurationRules rules(ConfigurationConvention::kAbb, controller);
  const Eigen::Isometry3d T_meas_wobj = controller.model().base() * T_base_wobj;
  for (size_t i = 1; i < after.size(); ++i) {
    const auto s = rules.Solve(ik, T_meas_wobj * after[i].T_frame_tool, after[i].configuration, Eigen::VectorXd());
    ASSERT_TRUE(s.found) << i;
    const Vector6d e = PoseError(identified.model().ForwardKinematics(s.q), T_meas_wobj * before[i].T_frame_tool);
    EXPECT_LE(e.head<3>().norm(), 1e-8) << i;  // the options' decimals: 1e-5 mm
    EXPECT_LE(e.tail<3>().norm(), 1e-8) << i;
  }
}

// The same work object and tool from a --filter-options file: the same bytes as with the flags; a bad
// value in the file: exit 2, one line naming the file, line and column, no output.
TEST(FilterCommand, FilterOptionsFileGivesWhatTheFlagsGive) {
  Files f;
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot controller = ControllerRobot(nominal, ReadRobotFile(f.identified));
  const Eigen::Isometry3d T_base_wobj = PoseFromXyzRpy({0.3, -0.1, 0.05}, {0.0, 0.0, 0.5});
  testing::WriteText(f.dir.path("w.mod"),
                     testing::RapidModule(controller, testing::Configurations(controller, 10, 7), 1000, T_base_wobj));
  const auto flags = RunKincal(f.Args(f.dir.path("w.mod"), f.dir.path("flags.mod")) +
                               " --work-object \"300 -100 50 28.6 0 0\" --tool \"10 0 150 0 17.2 0\"");
  ASSERT_EQ(flags.exit_code, 0) << flags.err;
  testing::WriteText(f.dir.path("filter.yaml"),
                     "# frames\nwork_object: [300, -100, 50, 28.6, 0, 0]\ntool: [10, 0, 150, 0, 17.2, 0]\n");
  const auto file =
      RunKincal(f.Args(f.dir.path("w.mod"), f.dir.path("file.mod")) + " --filter-options " + f.dir.path("filter.yaml"));
  ASSERT_EQ(file.exit_code, 0) << file.err;
  EXPECT_EQ(testing::ReadText(f.dir.path("file.mod")), testing::ReadText(f.dir.path("flags.mod")));

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"work_object: [300, -100, 50, 28.6, 0, 0]\ntool: [10, 0, 150]\n", "line 2, column 7:"},
      {"keep_tolerance: -1\n", "line 1, column 17:"},
      {"tool: [1, 2, 3, 4, 5, x]\n", "line 1, column 7:"},
      {"work_objekt: [0, 0, 0, 0, 0, 0]\n", "line 1, column 14:"},
  };
  for (const auto& [text, where] : bad) {
    testing::WriteText(f.dir.path("bad.yaml"), text);
    const auto r =
        RunKincal(f.Args(f.dir.path("w.mod"), f.dir.path("bad.mod")) + " --filter-options " + f.dir.path("bad.yaml"));
    EXPECT_EQ(r.exit_code, 2) << text;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("bad.yaml: " + where), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(f.dir.path("bad.mod")));
  }
}

}  // namespace
}  // namespace kincal
