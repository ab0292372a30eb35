// URDF in and out, and exact conversions between every pair of conventions.
// The written URDFs are read back by an independent reader: urdfdom's parser (not kincal's code) and
// orocos KDL's chain composition (as kdl_parser builds it: each segment a joint at the origin's position
// with the axis turned by the origin's rotation, then the origin frame).
#include <algorithm>
#include <set>

#include <gtest/gtest.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include "framework/random.h"
#include "models/conversion.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/mdh_model.h"
#include "models/model_factory.h"
#include "models/poe_model.h"
#include "robot/urdf_io.h"
#include "models/urdf_model.h"
#include "tests/support/kdl_reference.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::FromKdl;
using testing::ToKdl;

const std::vector<std::string> kConventions = ModelConventions();
std::string Irb120Urdf() { return testing::SourcePath("tests/data/irb120_3_58.urdf"); }

Eigen::VectorXd RandomQ(const Robot& robot, Rng* rng) {
  Eigen::VectorXd q(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) q[j] = rng->Uniform(robot.Limit(j).first, robot.Limit(j).second);
  return q;
}

double PoseGap(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::max((a.translation() - b.translation()).norm(), (a.linear() - b.linear()).cwiseAbs().maxCoeff());
}

// Largest pose difference of two models over random configurations (m; rotation matrix entries).
double Gap(const KinematicModel& a, const KinematicModel& b, uint64_t seed) {
  Rng rng(seed);
  double worst = 0;
  for (int t = 0; t < 100; ++t) {
    Eigen::VectorXd q(a.dof());
    for (int j = 0; j < a.dof(); ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    worst = std::max(worst, PoseGap(a.ForwardKinematics(q), b.ForwardKinematics(q)));
  }
  return worst;
}

// The independent reader: urdfdom's model of `text`, composed in KDL from `base` to `tip`.
KDL::Chain KdlChainFromUrdf(const std::string& text, const std::string& base, const std::string& tip) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  if (!model) throw std::runtime_error("urdfdom did not parse the URDF");
  std::vector<urdf::JointConstSharedPtr> joints;
  for (auto link = model->getLink(tip); link->name != base;
       link = model->getLink(link->parent_joint->parent_link_name)) {
    joints.insert(joints.begin(), link->parent_joint);
  }
  KDL::Chain chain;
  for (const auto& j : joints) {
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    const KDL::Frame F(KDL::Rotation::Quaternion(o.rotation.x, o.rotation.y, o.rotation.z, o.rotation.w),
                       KDL::Vector(o.position.x, o.position.y, o.position.z));
    const KDL::Vector axis = F.M * KDL::Vector(j->axis.x, j->axis.y, j->axis.z);
    KDL::Joint joint(j->name, KDL::Joint::None);
    if (j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS) {
      joint = KDL::Joint(j->name, F.p, axis, KDL::Joint::RotAxis);
    } else if (j->type == urdf::Joint::PRISMATIC) {
      joint = KDL::Joint(j->name, F.p, axis, KDL::Joint::TransAxis);
    }
    chain.addSegment(KDL::Segment(j->child_link_name, joint, F));
  }
  return chain;
}

double GapToUrdf(const KinematicModel& model, const Eigen::Isometry3d& T_urdf_meas, const KDL::Chain& chain,
                 uint64_t seed) {
  EXPECT_EQ(static_cast<int>(chain.getNrOfJoints()), model.dof());
  KDL::ChainFkSolverPos_recursive fk(chain);
  Rng rng(seed);
  double worst = 0;
  for (int t = 0; t < 100; ++t) {
    Eigen::VectorXd q(model.dof());
    for (int j = 0; j < model.dof(); ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    KDL::Frame f;
    EXPECT_GE(fk.JntToCart(ToKdl(q), f), 0);
    worst = std::max(worst, PoseGap(T_urdf_meas * model.ForwardKinematics(q), FromKdl(f)));
  }
  return worst;
}

// ---- Conversions -------------------------------------------------------------------------------------

TEST(Conversion, SeedArmToEveryConventionAndBackKeepsTheKinematics) {
  const Robot seed = testing::SeedTruth();
  for (const auto& to : kConventions) {
    const auto converted = ConvertModel(seed.model(), to);
    EXPECT_EQ(converted->convention(), to);
    EXPECT_LT(Gap(seed.model(), *converted, 1), 1e-9) << "mdh -> " << to;
    for (const auto& back : kConventions) {
      const auto again = ConvertModel(*converted, back);
      EXPECT_LT(Gap(seed.model(), *again, 2), 1e-9) << "mdh -> " << to << " -> " << back;
    }
  }
}

TEST(Conversion, MdhToDhIsTheRegroupingOfRows) {
  const Robot seed = testing::SeedTruth();
  const auto dh = ConvertModel(seed.model(), "dh");
  const int n = seed.dof();
  for (int i = 1; i <= n; ++i) {
    const std::string s = "_" + std::to_string(i), next = "_" + std::to_string(i + 1);
    EXPECT_EQ(dh->Parameter("theta" + s), seed.model().Parameter("theta" + s));
    EXPECT_EQ(dh->Parameter("d" + s), seed.model().Parameter("d" + s));
    EXPECT_EQ(dh->Parameter("a" + s), i < n ? seed.model().Parameter("a" + next) : 0.0);
    EXPECT_EQ(dh->Parameter("alpha" + s), i < n ? seed.model().Parameter("alpha" + next) : 0.0);
  }
}

TEST(Conversion, RandomArmsWithPrismaticJointsBetweenEveryPair) {
  using J = JointType;
  const std::vector<std::vector<J>> arms = {
      {J::kRevolute, J::kRevolute, J::kRevolute, J::kRevolute, J::kRevolute, J::kRevolute},
      {J::kRevolute, J::kPrismatic, J::kRevolute, J::kRevolute},
      {J::kPrismatic, J::kRevolute, J::kPrismatic}};
  uint64_t seed = 40;
  for (const auto& joints : arms) {
    for (const auto& from : kConventions) {
      auto model = ConvertModel(MdhModel(joints), from);  // the right type
      model = testing::RandomizedModel(std::move(model), ++seed);
      for (const auto& to : kConventions) {
        std::unique_ptr<KinematicModel> converted;
        ASSERT_NO_THROW(converted = ConvertModel(*model, to)) << from << " -> " << to;
        EXPECT_LT(Gap(*model, *converted, seed), 1e-9 * 5) << from << " -> " << to;
      }
    }
  }
}

TEST(Conversion, ParallelAxesGoToMdhExactly) {
  // The IRB 120's joints 2 and 3 are parallel: POE -> MDH must still be exact (d through the normal's foot).
  const Robot irb = testing::LoadExampleRobot("irb120_mdh.yaml");
  const auto poe = ConvertModel(irb.model(), "poe");
  const auto mdh = ConvertModel(*poe, "mdh");
  EXPECT_LT(Gap(irb.model(), *mdh, 3), 1e-12);
  EXPECT_NEAR(mdh->Parameter("alpha_3"), 0.0, 1e-12);
}

TEST(Conversion, UnknownConventionIsOneLine) {
  try {
    ConvertModel(MdhModel(3), "screw");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("mdh to screw"), std::string::npos) << e.what();
  }
}

// ---- The urdf convention -----------------------------------------------------------------------------

TEST(UrdfModel, AxisAnglesAndJointsRoundTrip) {
  UrdfModel m(2);
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 0, 0),
                                      Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0.3, -0.4, 0.5)}) {
    const Eigen::Isometry3d T = PoseFromXyzRpy(Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(0.4, -0.5, 0.6));
    m.SetJoint(1, T, axis);
    EXPECT_LT((m.JointAxis(1) - axis.normalized()).norm(), 1e-15);
    EXPECT_LT((m.JointOrigin(1).matrix() - T.matrix()).norm(), 1e-15);
    // q about the axis, as URDF defines it: child = origin * Rot(axis, q).
    Eigen::VectorXd q(2);
    q << 0.0, 0.7;
    const Eigen::Isometry3d expected = m.JointOrigin(0) * m.JointOrigin(1) * Eigen::AngleAxisd(0.7, axis.normalized());
    EXPECT_LT(PoseGap(m.ForwardKinematics(q), expected), 1e-15);
  }
}

// ---- Import ------------------------------------------------------------------------------------------

TEST(UrdfImport, RosIndustrialIrb120MatchesKincalsIrb120File) {
  // The URDF's tool0 is kincal's frame 6 (tool identity); both have the same joint zeros and directions,
  // and the base link is kincal's base frame, so the poses agree at every configuration as they are.
  const Robot file = testing::LoadExampleRobot("irb120_mdh.yaml");
  for (const std::string convention : {"urdf", "mdh", "poe", "dh"}) {
    const Robot urdf = ImportUrdf(Irb120Urdf(), {"base_link", "tool0", convention});
    ASSERT_EQ(urdf.dof(), 6);
    EXPECT_EQ(urdf.model().convention(), convention);
    Rng rng(7);
    double worst = 0;
    for (int t = 0; t < 200; ++t) {
      const Eigen::VectorXd q = RandomQ(file, &rng);
      worst = std::max(worst, PoseGap(urdf.model().ForwardKinematics(q), file.model().ForwardKinematics(q)));
    }
    EXPECT_LT(worst, 1e-12) << convention;
  }
  const Robot urdf = ImportUrdf(Irb120Urdf(), {"base_link", "tool0", "urdf"});
  ASSERT_TRUE(urdf.urdf.has_value());
  EXPECT_EQ(urdf.urdf->joints,
            (std::vector<std::string>{"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"}));
  ASSERT_EQ(urdf.limits.size(), 6u);
  EXPECT_DOUBLE_EQ(urdf.limits[2].second, 1.22173);
  ASSERT_EQ(urdf.velocity_limits.size(), 6);
  EXPECT_DOUBLE_EQ(urdf.velocity_limits[5], 7.33038);
  EXPECT_NEAR(urdf.model().Parameter("axis_tilt_2"), M_PI / 2, 1e-15);  // axis y
  EXPECT_NEAR(urdf.model().Parameter("axis_azimuth_2"), M_PI / 2, 1e-15);
  EXPECT_NEAR(urdf.model().Parameter("z_2"), 0.29, 1e-15);
}

std::string ImportError(const std::string& text, const std::string& base, const std::string& tip) {
  testing::TempDir dir;
  testing::WriteText(dir.path("r.urdf"), text);
  try {
    ImportUrdf(dir.path("r.urdf"), {base, tip, "urdf"});
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("r.urdf"), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(UrdfImport, BadFilesGiveOneLine) {
  const std::string two = R"(<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
    <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="0" velocity="1"/></joint>
    <joint name="j2" type="JOINT"><parent link="a"/><child link="c"/></joint></robot>)";
  auto with = [&](const std::string& type) {
    std::string t = two;
    return t.replace(t.find("JOINT"), 5, type);
  };
  EXPECT_NE(ImportError(with("floating"), "a", "c").find("floating"), std::string::npos);
  EXPECT_NE(ImportError(with("planar"), "a", "c").find("planar"), std::string::npos);
  EXPECT_NE(ImportError(with("fixed"), "b", "c").find("no serial chain"), std::string::npos);
  EXPECT_NE(ImportError(with("fixed"), "a", "nowhere").find("no link 'nowhere'"), std::string::npos);
  EXPECT_NE(ImportError("<robot name=\"r\"><link name=\"a\">\n</robot>", "a", "a").find(":2:"), std::string::npos);
  EXPECT_NE(
      ImportError("<robot name=\"r\"><joint name=\"j\" type=\"revolute\"/></robot>", "a", "a").find("not a valid URDF"),
      std::string::npos);
}

// ---- Export ------------------------------------------------------------------------------------------

TEST(UrdfExport, SeedArmReadByAnIndependentReader) {
  const Robot seed = testing::SeedTruth();
  const std::string text = RobotToUrdf(seed);
  const KDL::Chain chain = KdlChainFromUrdf(text, "world", "tool0");
  EXPECT_LT(GapToUrdf(seed.model(), Eigen::Isometry3d::Identity(), chain, 5), 1e-9);
  // Every convention of the same arm writes the same kinematics.
  for (const auto& to : kConventions) {
    const Robot converted = seed.WithModel(ConvertModel(seed.model(), to));
    EXPECT_LT(GapToUrdf(seed.model(), Eigen::Isometry3d::Identity(),
                        KdlChainFromUrdf(RobotToUrdf(converted), "world", "tool0"), 6),
              1e-9)
        << to;
  }
  EXPECT_NE(text.find("lower=\"-2.9670597283903604\""), std::string::npos);  // -170 deg, all digits
}

// Every element and attribute of a and b, with the numbers of joint origins and limits compared to
// `tolerance` (those of `changed` joints may differ) and everything else exactly.
void ExpectSameTree(const TiXmlElement* a, const TiXmlElement* b, const std::string& joint = "") {
  ASSERT_TRUE(a && b);
  ASSERT_EQ(std::string(a->Value()), std::string(b->Value()));
  const std::string name = a->Attribute("name") ? a->Attribute("name") : "";
  const bool numbers = !joint.empty() && (std::string(a->Value()) == "origin" || std::string(a->Value()) == "limit");
  std::set<std::string> attributes;
  for (auto* x = a->FirstAttribute(); x; x = x->Next()) attributes.insert(x->Name());
  for (auto* x = b->FirstAttribute(); x; x = x->Next()) attributes.insert(x->Name());
  for (const auto& key : attributes) {
    ASSERT_TRUE(a->Attribute(key.c_str()) && b->Attribute(key.c_str())) << key << " of " << a->Value();
    if (numbers && key != "effort") continue;  // the kinematic numbers: checked through the kinematics
    EXPECT_EQ(std::string(a->Attribute(key.c_str())), std::string(b->Attribute(key.c_str())))
        << key << " of " << a->Value() << " " << name;
  }
  const TiXmlNode* x = a->FirstChild();
  const TiXmlNode* y = b->FirstChild();
  for (; x && y; x = x->NextSibling(), y = y->NextSibling()) {
    ASSERT_EQ(x->Type(), y->Type());
    if (x->ToElement()) {
      const bool in_joint = std::string(a->Value()) == "joint";
      ExpectSameTree(x->ToElement(), y->ToElement(), in_joint ? name : joint);
    } else {
      EXPECT_EQ(std::string(x->Value()), std::string(y->Value()));  // comments, text
    }
  }
  EXPECT_TRUE(!x && !y) << "different number of children in " << a->Value() << " " << name;
}

TEST(UrdfExport, RoundTripKeepsEverythingButTheKinematicNumbers) {
  const std::string original = testing::ReadText(Irb120Urdf());
  TiXmlDocument source;
  source.Parse(original.c_str());
  for (const std::string convention : {"urdf", "mdh", "poe"}) {
    Robot robot = ImportUrdf(Irb120Urdf(), {"base_link", "tool0", convention});
    {
      // Unchanged: the file comes back as it was, numbers included.
      TiXmlDocument out;
      out.Parse(RobotToUrdf(robot).c_str());
      ExpectSameTree(source.RootElement(), out.RootElement());
    }
    // "Calibrated": every geometric parameter moved a little (millimetres, milliradians), base too.
    Rng rng(11);
    Eigen::VectorXd p = robot.model().Parameters();
    for (int i = 0; i < p.size(); ++i) p[i] += rng.Uniform(-2e-3, 2e-3);
    robot.model().SetParameters(p);
    robot.limits[0].first = -2.5;
    const std::string text = RobotToUrdf(robot);
    TiXmlDocument out;
    out.Parse(text.c_str());
    ExpectSameTree(source.RootElement(), out.RootElement(), "");
    // The kinematics are the robot's (base link = measurement frame), by the independent reader.
    const KDL::Chain chain = KdlChainFromUrdf(text, "base_link", "tool0");
    EXPECT_LT(GapToUrdf(robot.model(), Eigen::Isometry3d::Identity(), chain, 9), 1e-9) << convention;
    // Axes unchanged, limits written.
    EXPECT_EQ(text.find("lower=\"-2.87979\""), std::string::npos);
    EXPECT_NE(text.find("lower=\"-2.5\""), std::string::npos);
  }
}

TEST(UrdfExport, ReimportOfTheWrittenUrdfHasTheSameKinematics) {
  Robot robot = ImportUrdf(Irb120Urdf(), {"base_link", "tool0", "mdh"});
  Eigen::VectorXd p = robot.model().Parameters();
  Rng rng(3);
  for (int i = 0; i < p.size(); ++i) p[i] += rng.Uniform(-1e-3, 1e-3);
  robot.model().SetParameters(p);
  testing::TempDir dir;
  testing::WriteText(dir.path("calibrated.urdf"), RobotToUrdf(robot));
  const Robot again = ImportUrdf(dir.path("calibrated.urdf"), {"base_link", "tool0", "urdf"});
  EXPECT_LT(Gap(robot.model(), again.model(), 4), 1e-12);
}

}  // namespace
}  // namespace kincal
