// kincal import and kincal convert --to (every convention, and URDF) end to end: the files written by the
// program have the forward kinematics of the robot they came from, and bad URDFs give exit status 2 and
// one line.
#include <algorithm>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/model_factory.h"
#include "robot/robot_file.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;

double Gap(const Robot& a, const Robot& b, uint64_t seed) {
  Rng rng(seed);
  double worst = 0;
  for (int t = 0; t < 100; ++t) {
    Eigen::VectorXd q(a.dof());
    for (int j = 0; j < a.dof(); ++j) q[j] = rng.Uniform(a.Limit(j).first, a.Limit(j).second);
    const Eigen::Isometry3d Ta = a.model().ForwardKinematics(q), Tb = b.model().ForwardKinematics(q);
    worst = std::max(
        {worst, (Ta.translation() - Tb.translation()).norm(), (Ta.linear() - Tb.linear()).cwiseAbs().maxCoeff()});
  }
  return worst;
}

TEST(UrdfCli, ConvertSeedArmToEveryConvention) {
  testing::TempDir dir;
  const std::string seed = SourcePath("examples/robots/seed_identified.yaml");
  const Robot original = ReadRobotFile(seed);
  for (const std::string& to : ModelConventions()) {
    const auto r = RunKincal("convert " + seed + " --to " + to + " --out " + dir.path(to + ".yaml"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Robot converted = ReadRobotFile(dir.path(to + ".yaml"));
    EXPECT_EQ(converted.model().convention(), to);
    // Through the file's text (mm, deg, shortest exact digits): 1e-9 m.
    EXPECT_LT(Gap(original, converted, 1), 1e-9) << to;
    EXPECT_EQ(converted.limits, original.limits);
    ASSERT_TRUE(converted.drives.has_value()) << "drives carried through";
    EXPECT_EQ(converted.drives->ratio, original.drives->ratio);
  }
}

TEST(UrdfCli, ImportEditAndWriteBack) {
  testing::TempDir dir;
  const std::string urdf = SourcePath("tests/data/irb120_3_58.urdf");
  auto r = RunKincal("import " + urdf + " --base base_link --tip tool0 --convention mdh --out " + dir.path("irb.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Robot imported = ReadRobotFile(dir.path("irb.yaml"));
  EXPECT_LT(Gap(imported, ReadRobotFile(SourcePath("examples/robots/irb120_mdh.yaml")), 2), 1e-9);
  ASSERT_TRUE(imported.urdf.has_value());
  EXPECT_EQ(imported.urdf->tip_link, "tool0");
  // Unchanged robot: the URDF comes back line for line (TinyXML's printer, same indentation).
  r = RunKincal("convert " + dir.path("irb.yaml") + " --to urdf --out " + dir.path("back.urdf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string original = testing::ReadText(urdf), back = testing::ReadText(dir.path("back.urdf"));
  EXPECT_NE(back.find("irb120_3_58/visual/link_4.stl"), std::string::npos);
  EXPECT_NE(back.find("izz=\"0.0472376\""), std::string::npos);
  EXPECT_NE(back.find("Test fixture: ROS-Industrial"), std::string::npos);
  // Re-import of the written file: the same kinematics.
  r = RunKincal("import " + dir.path("back.urdf") + " --base base_link --tip tool0 --out " + dir.path("again.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(Gap(imported, ReadRobotFile(dir.path("again.yaml")), 3), 1e-9);
}

TEST(UrdfCli, BadUrdfIsExitTwoAndOneLine) {
  testing::TempDir dir;
  testing::WriteText(dir.path("float.urdf"), R"(<robot name="r"><link name="a"/><link name="b"/>
    <joint name="j" type="floating"><parent link="a"/><child link="b"/></joint></robot>)");
  testing::WriteText(dir.path("broken.urdf"), "<robot name=\"r\">\n  <link name=\"a\">\n</robot>\n");
  const std::string out = dir.path("out.yaml");
  for (const std::string& args :
       {"import " + dir.path("float.urdf") + " --base a --tip b --out " + out,
        "import " + dir.path("broken.urdf") + " --base a --tip a --out " + out,
        "import " + SourcePath("tests/data/irb120_3_58.urdf") + " --base tool0 --tip base_link --out " + out,
        "import " + SourcePath("tests/data/irb120_3_58.urdf") +
            " --base base_link --tip tool0 --convention screw --out " + out}) {
    const auto r = RunKincal(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << "no output on error";
  }
}

}  // namespace
}  // namespace kincal
