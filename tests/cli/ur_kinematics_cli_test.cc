// UR kinematics YAML in and out (robot/ur_kinematics.h) through the command line. The reference is the
// chain as ur_description builds it, composed here from the file's numbers with yaml-cpp and plain
// Eigen (origin xyz, then Rz(yaw) Ry(pitch) Rx(roll), then Rz(q), per joint), not kincal's models.
#include <regex>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "framework/dataset.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;

const char* const kJoints[6] = {"shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"};

// A UR10e-like calibration: the default geometry (ur_description's shape: roll +-pi/2 between the
// shoulder and upper arm and around wrist 2; pitch pi on wrist 3) with every number moved at random.
std::string RandomUrFile(uint64_t seed) {
  const double base[6][6] = {{0, 0, 0.1807, 0, 0, 0},        {0, 0, 0, M_PI / 2, 0, 0},
                             {-0.6127, 0, 0, 0, 0, 0},       {-0.57155, 0, 0.17415, 0, 0, 0},
                             {0, -0.11985, 0, M_PI / 2, 0, 0}, {0, 0.11655, 0, M_PI / 2, M_PI, M_PI}};
  Rng rng(seed);
  std::string text = "# a calibration\nkinematics:\n";
  char number[64];
  for (int i = 0; i < 6; ++i) {
    text += std::string("  ") + kJoints[i] + ":\n";
    const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
    for (int k = 0; k < 6; ++k) {
      std::snprintf(number, sizeof number, "%.17g", base[i][k] + rng.Uniform(-1e-3, 1e-3));
      text += std::string("    ") + keys[k] + ": " + number + "\n";
    }
  }
  return text + "  hash: calib_1234567890\n";
}

// ur_description's chain from base_link_inertia to wrist_3_link (= tool0) of the file's numbers.
Eigen::Isometry3d ReferenceChain(const YAML::Node& file, const Eigen::VectorXd& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) {
    const YAML::Node j = file["kinematics"][kJoints[i]];
    T.translate(Eigen::Vector3d(j["x"].as<double>(), j["y"].as<double>(), j["z"].as<double>()));
    T.rotate(Eigen::AngleAxisd(j["yaw"].as<double>(), Eigen::Vector3d::UnitZ()));
    T.rotate(Eigen::AngleAxisd(j["pitch"].as<double>(), Eigen::Vector3d::UnitY()));
    T.rotate(Eigen::AngleAxisd(j["roll"].as<double>(), Eigen::Vector3d::UnitX()));
    T.rotate(Eigen::AngleAxisd(q[i], Eigen::Vector3d::UnitZ()));
  }
  return T;
}

double PositionGap(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}
double AngleGap(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

Eigen::VectorXd RandomQ(Rng* rng) {
  Eigen::VectorXd q(6);
  for (int j = 0; j < 6; ++j) q[j] = rng->Uniform(-2 * M_PI, 2 * M_PI);
  return q;
}

TEST(UrKinematicsCli, RoundTripKeepsTheChainOfUrDescription) {
  testing::TempDir dir;
  testing::WriteText(dir.path("k.yaml"), RandomUrFile(7));
  auto r = RunKincal("import " + dir.path("k.yaml") + " --out " + dir.path("r.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunKincal("convert " + dir.path("r.yaml") + " --to ur-kinematics --out " + dir.path("k2.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // nothing dropped
  r = RunKincal("import " + dir.path("k2.yaml") + " --out " + dir.path("r2.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const YAML::Node file = YAML::LoadFile(dir.path("k.yaml"));
  const Robot first = ReadRobotFile(dir.path("r.yaml")), second = ReadRobotFile(dir.path("r2.yaml"));
  Rng rng(11);
  double position = 0, angle = 0;
  for (int t = 0; t < 10000; ++t) {
    const Eigen::VectorXd q = RandomQ(&rng);
    const Eigen::Isometry3d reference = ReferenceChain(file, q);
    for (const Robot* robot : {&first, &second}) {
      const Eigen::Isometry3d T = robot->model().ForwardKinematics(q);
      position = std::max(position, PositionGap(T, reference));
      angle = std::max(angle, AngleGap(T, reference));
    }
  }
  EXPECT_LT(position, 1e-9);
  EXPECT_LT(angle, 1e-9);
  // Read and written back unchanged, the numbers are the file's.
  const YAML::Node back = YAML::LoadFile(dir.path("k2.yaml"));
  for (int i = 0; i < 6; ++i) {
    for (const char* key : {"x", "y", "z", "roll", "pitch", "yaw"}) {
      EXPECT_EQ(back["kinematics"][kJoints[i]][key].as<double>(), file["kinematics"][kJoints[i]][key].as<double>());
    }
  }
}

// Any 6R robot: the file holds the chain from the base frame, the tool and base are reported (stderr and
// the file's comments), and the joint-level terms' effect is measured on data.
TEST(UrKinematicsCli, AnySixJointRobotWithWhatItCannotHold) {
  testing::TempDir dir;
  Robot truth = testing::LoadExampleRobot("ur10_joint_errors.yaml");
  Rng rng(5);
  Eigen::VectorXd p = truth.model().Parameters();
  for (int i = 0; i < p.size(); ++i) p[i] += rng.Uniform(-1e-3, 1e-3);  // an identified arm: no exact angle
  truth.model().SetParameters(p);
  truth.model().SetBase(PoseFromXyzRpy({1.2, -0.4, 0.3}, {0.01, -0.02, 2.0}));
  Eigen::VectorXd c = truth.joint_errors.Coefficients();
  for (int i = 0; i < c.size(); ++i) c[i] = rng.Uniform(-1e-4, 1e-4);
  truth.joint_errors.SetCoefficients(c);
  WriteRobotFile(truth, dir.path("truth.yaml"));
  WriteDataset(testing::RandomPoses(truth, truth, 40), dir.path("data.csv"));

  auto r = RunKincal("convert " + dir.path("truth.yaml") + " --to ur-kinematics --out " + dir.path("k.yaml") +
                     " --data " + dir.path("data.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* item : {"base not held", "tool not held", "joint errors not held"}) {
    EXPECT_NE(r.err.find(item), std::string::npos) << item << "\n" << r.err;
    EXPECT_NE(testing::ReadText(dir.path("k.yaml")).find("# " + std::string(item)), std::string::npos) << item;
  }
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("error ([-0-9.e+]+) mm with .*, ([-0-9.e+]+) mm as"))) << r.out;
  EXPECT_LT(std::stod(m[1]), 1e-6);  // noise-free data of the robot itself
  EXPECT_GT(std::stod(m[2]), 1e-3);  // 1e-4 rad joint errors on a 1.3 m arm

  r = RunKincal("import " + dir.path("k.yaml") + " --out " + dir.path("back.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Robot back = ReadRobotFile(dir.path("back.yaml"));
  const YAML::Node written = YAML::LoadFile(dir.path("k.yaml"));
  // T_meas_tool = base * chain(q) * tool' for one constant tool', the chain ur_description's of the file.
  const Eigen::Isometry3d base = truth.model().base();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  const Eigen::Isometry3d tool =
      (base * back.model().ForwardKinematics(zero)).inverse() * truth.model().ForwardKinematics(zero);
  double position = 0, angle = 0;
  for (int t = 0; t < 10000; ++t) {
    const Eigen::VectorXd q = RandomQ(&rng);
    const Eigen::Isometry3d expected = truth.model().ForwardKinematics(q);
    const Eigen::Isometry3d T = base * ReferenceChain(written, q) * tool;
    EXPECT_LT(PositionGap(back.model().ForwardKinematics(q), ReferenceChain(written, q)), 1e-9);
    position = std::max(position, PositionGap(T, expected));
    angle = std::max(angle, AngleGap(T, expected));
  }
  EXPECT_LT(position, 1e-9);
  EXPECT_LT(angle, 1e-9);
}

TEST(UrKinematicsCli, BadFilesOneLineWithLineAndColumn) {
  testing::TempDir dir;
  const std::string good = RandomUrFile(1);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"kinematics:\n  shoulder: {x: 0, y: a}\n", ":2:"},                          // not a number
      {"kinematics:\n  shoulder: [x: 0\n", ":"},                                    // YAML syntax
      {"kinematic:\n  shoulder: {}\n", ":1:1:"},                                    // not the format
      {std::regex_replace(good, std::regex("  wrist_2:"), "  wrist_two:"), ":"},  // unknown joint
      {std::regex_replace(good, std::regex("    pitch: [^\n]*\n"), "", std::regex_constants::format_first_only),
       ":"},  // a joint lacks a key
  };
  for (const auto& [text, where] : cases) {
    testing::WriteText(dir.path("bad.yaml"), text);
    const auto r = RunKincal("import " + dir.path("bad.yaml") + " --out " + dir.path("out.yaml"));
    EXPECT_EQ(r.exit_code, 2) << text;
    EXPECT_TRUE(std::regex_search(r.err, std::regex("bad\\.yaml:[0-9]+:[0-9]+: "))) << r.err;
    EXPECT_NE(r.err.find("bad.yaml" + where), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  // A robot that is not 6R is refused with one line.
  testing::WriteText(dir.path("two.yaml"),
                     "name: two\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints:\n"
                     "  - {alpha: 0, a: 0, theta: 0, d: 0}\n  - {alpha: 0, a: 100, theta: 0, d: 0}\n");
  const auto r = RunKincal("convert " + dir.path("two.yaml") + " --to ur-kinematics --out " + dir.path("k.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("two.yaml: a UR kinematics file holds 6 revolute joints"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
}  // namespace kincal
