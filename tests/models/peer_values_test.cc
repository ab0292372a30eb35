// Forward kinematics against numbers published in other projects' test suites. Each test names its source
// (repository and file); the models are built from the same tables those projects use, and the tolerances
// are the ones the sources assert with (their numbers are rounded to 4 or 6 decimals).
#include <array>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/mdh_model.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::LoadExampleRobot;

Eigen::Matrix4d Rows(std::initializer_list<double> values) {
  Eigen::Matrix4d m;
  auto it = values.begin();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = *it++;
  }
  return m;
}

// alpha, a, theta, d per row (the parameter order of kincal's DH-family models).
void SetTable(KinematicModel* model, const std::vector<std::array<double, 4>>& rows) {
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::string s = "_" + std::to_string(i + 1);
    model->SetParameter("alpha" + s, rows[i][0]);
    model->SetParameter("a" + s, rows[i][1]);
    model->SetParameter("theta" + s, rows[i][2]);
    model->SetParameter("d" + s, rows[i][3]);
  }
}

Eigen::VectorXd Q(std::initializer_list<double> values) {
  Eigen::VectorXd q(static_cast<Eigen::Index>(values.size()));
  int i = 0;
  for (double v : values) q[i++] = v;
  return q;
}

constexpr double kDeg = M_PI / 180.0;

// ---- pybotics (engnadeau/pybotics): UR10, modified DH, millimetres ---------------------------------
// Model: robot-models/ur10-mdh.csv (rows alpha, a, theta, d; pi written to 14 digits as in the file).
// Values: tests/test_robot.py (test_fk, asserted to 1e-6) and tests/resources/ur10-joints-poses.csv.
MdhModel PyboticsUr10() {
  MdhModel model(6);
  SetTable(&model, {{0, 0, 0, 118},
                    {1.5707963267949, 0, 3.14159265358979, 0},
                    {0, 612.7, 0, 0},
                    {0, 571.6, 0, 163.9},
                    {-1.5707963267949, 0, 0, 115.7},
                    {1.5707963267949, 0, 3.14159265358979, 92.2}});
  return model;
}

TEST(PeerValues, PyboticsUr10AtItsTestPose) {
  const Eigen::Matrix4d expected = Rows({0, 0, -1, -663.8, -1, 0, 0, -163.9, 0, 1, 0, 615, 0, 0, 0, 1});
  const Eigen::Matrix4d T = PyboticsUr10().ForwardKinematics(Q({0, -90 * kDeg, 90 * kDeg, 0, 90 * kDeg, 0})).matrix();
  EXPECT_LT((T - expected).cwiseAbs().maxCoeff(), 1e-6) << T;
}

TEST(PeerValues, PyboticsUr10JointsPosesCsv) {
  // The file's single row: joints 10, 20, ..., 60 deg and the 16 entries of the pose, row-major, 6 decimals.
  const Eigen::Matrix4d expected = Rows({-0.786357, -0.607604, 0.111619, -776.143784,  //
                                         -0.527587, 0.566511, -0.633022, -363.462788,  //
                                         0.321394, -0.556670, -0.766044, -600.056043,  //
                                         0, 0, 0, 1});
  const Eigen::Matrix4d T =
      PyboticsUr10().ForwardKinematics(Q({10 * kDeg, 20 * kDeg, 30 * kDeg, 40 * kDeg, 50 * kDeg, 60 * kDeg})).matrix();
  EXPECT_LT((T.topLeftCorner<3, 3>() - expected.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff(), 5e-7) << T;
  EXPECT_LT((T.topRightCorner<3, 1>() - expected.topRightCorner<3, 1>()).cwiseAbs().maxCoeff(), 5e-7) << T;
}

// ---- Robotics Toolbox for Python (petercorke/robotics-toolbox-python): Panda, modified DH ----------
// Model: roboticstoolbox/models/DH/Panda.py (7 RevoluteMDH links, flange d7 = 0.107 m, tool
// transl(0, 0, 0.103) * trotz(-pi/4)). Values: tests/test_DHRobot.py, test_fkine_panda and
// test_fkine_all, asserted to 4 decimals.
MdhModel RtbPanda() {
  MdhModel model(7);
  SetTable(&model, {{0, 0, 0, 0.333},
                    {-M_PI / 2, 0, 0, 0},
                    {M_PI / 2, 0, 0, 0.316},
                    {M_PI / 2, 0.0825, 0, 0},
                    {-M_PI / 2, -0.0825, 0, 0.384},
                    {M_PI / 2, 0, 0, 0},
                    {M_PI / 2, 0.088, 0, 0.107}});
  model.SetTool(PoseFromXyzRpy({0, 0, 0.103}, {0, 0, -M_PI / 4}));
  return model;
}

TEST(PeerValues, RoboticsToolboxPythonPandaFkine) {
  const Eigen::Matrix4d expected = Rows({-0.8583, 0.1178, 0.4994, 0.1372,   //
                                         0.1980, 0.9739, 0.1106, 0.3246,    //
                                         -0.4734, 0.1938, -0.8593, 0.4436,  //
                                         0, 0, 0, 1});
  const Eigen::Matrix4d T = RtbPanda().ForwardKinematics(Q({1, 2, 3, 4, 5, 6, 7})).matrix();
  EXPECT_LT((T - expected).cwiseAbs().maxCoeff(), 1e-4) << T;
}

TEST(PeerValues, RoboticsToolboxPythonPandaFkineAll) {
  // fkine_all: the frame of every link, 1..7 (no tool).
  const std::vector<Eigen::Matrix4d> expected = {
      Rows({0.5403, -0.8415, 0, 0, 0.8415, 0.5403, 0, 0, 0, 0, 1, 0.333, 0, 0, 0, 1}),
      Rows({-0.2248, -0.4913, -0.8415, 0, -0.3502, -0.7651, 0.5403, 0, -0.9093, 0.4161, 0, 0.333, 0, 0, 0, 1}),
      Rows({0.1038, 0.8648, 0.4913, 0.1552, 0.4229, -0.4855, 0.7651, 0.2418, 0.9002, 0.1283, -0.4161, 0.2015, 0, 0, 0,
            1}),
      Rows({-0.4397, -0.2425, -0.8648, 0.1638, -0.8555, -0.1801, 0.4855, 0.2767, -0.2735, 0.9533, -0.1283, 0.2758, 0, 0,
            0, 1}),
      Rows({-0.9540, -0.1763, -0.2425, 0.107, 0.2229, -0.9581, -0.1801, 0.2781, -0.2006, -0.2258, 0.9533, 0.6644, 0, 0,
            0, 1}),
      Rows({-0.8482, -0.4994, 0.1763, 0.107, 0.2643, -0.1106, 0.9581, 0.2781, -0.4590, 0.8593, 0.2258, 0.6644, 0, 0, 0,
            1}),
      Rows({-0.5236, 0.6902, 0.4994, 0.08575, 0.8287, 0.5487, 0.1106, 0.3132, -0.1977, 0.4718, -0.8593, 0.5321, 0, 0, 0,
            1})};
  const std::vector<Eigen::Isometry3d> frames = RtbPanda().FramePoses(Q({1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(frames.size(), 9u);  // base, frames 1..7, tool
  for (int i = 0; i < 7; ++i) {
    EXPECT_LT((frames[i + 1].matrix() - expected[i]).cwiseAbs().maxCoeff(), 1e-4) << "frame " << i + 1;
  }
}

// ---- Robotics Toolbox for MATLAB (petercorke/robotics-toolbox-matlab): Puma 560, standard DH ------
// Model: models/mdl_puma560.m, which examples/robots/puma560_dh.yaml transcribes (and puma560_mdh.yaml
// rewrites in modified DH). Values: unit_test/SerialLinkTest.m (the version with Test_jacob0, Test_jacobn
// and Test_ikine6s), asserted to 1e-4. jacob0 is the geometric Jacobian in the base frame (velocity of
// the tool origin, then angular velocity), kincal's layout; jacobn is the same in the tool frame.
const Eigen::VectorXd kQz = Q({0, 1, 0, 0, 2, 0});  // the test file's own "qz" and "qn"
const Eigen::VectorXd kQn = Q({0, M_PI / 4, -M_PI, 1, M_PI / 4, 0});

Matrix6Xd Rows6(std::initializer_list<double> values) {
  Matrix6Xd m(6, 6);
  auto it = values.begin();
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) m(r, c) = *it++;
  }
  return m;
}

Matrix6Xd InToolFrame(const KinematicModel& model, const Eigen::VectorXd& q) {
  const Eigen::Matrix3d R = model.ForwardKinematics(q).linear();
  Matrix6Xd J = model.JointJacobian(q);
  J.topRows<3>() = R.transpose() * J.topRows<3>();
  J.bottomRows<3>() = R.transpose() * J.bottomRows<3>();
  return J;
}

class RtbMatlabPuma : public ::testing::TestWithParam<const char*> {
 protected:
  const KinematicModel& model() {
    if (!robot_.has_model()) robot_ = LoadExampleRobot(GetParam());
    return robot_.model();
  }
  Robot robot_;
};

TEST_P(RtbMatlabPuma, Jacob0) {
  const Matrix6Xd at_qz = Rows6({0.1501,  -0.6137, -0.2504, 0,       0,       0,        //
                                 -0.1191, -0.0000, -0.0000, 0,       0,       0,        //
                                 -0.0000, -0.1191, -0.3524, 0,       0,       0,        //
                                 0,       -0.0000, -0.0000, -0.8415, -0.0000, -0.1411,  //
                                 0.0000,  -1.0000, -1.0000, -0.0000, -1.0000, -0.0000,  //
                                 1.0000,  0.0000,  0.0000,  0.5403,  0.0000,  -0.9900});
  const Matrix6Xd at_qn = Rows6({0.1501,  0.0144,  0.3197,  0,       0,       0,        //
                                 0.5963,  -0.0000, -0.0000, 0,       0,       0,        //
                                 -0.0000, 0.5963,  0.2910,  0,       0,       0,        //
                                 0.0000,  -0.0000, -0.0000, 0.7071,  -0.5950, 0.7702,   //
                                 -0.0000, -1.0000, -1.0000, 0,       -0.5403, -0.5950,  //
                                 1.0000,  0.0000,  0.0000,  -0.7071, -0.5950, -0.2298});
  EXPECT_LT((model().JointJacobian(kQz) - at_qz).cwiseAbs().maxCoeff(), 1e-4) << model().JointJacobian(kQz);
  EXPECT_LT((model().JointJacobian(kQn) - at_qn).cwiseAbs().maxCoeff(), 1e-4) << model().JointJacobian(kQn);
}

TEST_P(RtbMatlabPuma, Jacobn) {
  const Matrix6Xd at_qz = Rows6({-0.1485, 0.5908,  0.1982,  0,       0,       0,  //
                                 -0.1191, 0.0000,  0.0000,  0,       0,       0,  //
                                 -0.0212, 0.2045,  0.3842,  0,       0,       0,  //
                                 0.1411,  0,       0,       0.9093,  0,       0,  //
                                 -0.0000, -1.0000, -1.0000, -0.0000, -1.0000, 0,  //
                                 -0.9900, 0.0000,  0.0000,  -0.4161, 0.0000,  1.0000});
  const Matrix6Xd at_qn = Rows6({0.3893,  -0.4559, -0.1506, 0,       0,       0,  //
                                 0.4115,  0.3633,  0.3633,  0,       0,       0,  //
                                 -0.2392, -0.1260, 0.1793,  0,       0,       0,  //
                                 -0.7702, -0.5950, -0.5950, 0.7071,  0,       0,  //
                                 0.5950,  -0.5403, -0.5403, -0.0000, -1.0000, 0,  //
                                 -0.2298, 0.5950,  0.5950,  0.7071,  0.0000,  1.0000});
  EXPECT_LT((InToolFrame(model(), kQz) - at_qz).cwiseAbs().maxCoeff(), 1e-4) << InToolFrame(model(), kQz);
  EXPECT_LT((InToolFrame(model(), kQn) - at_qn).cwiseAbs().maxCoeff(), 1e-4) << InToolFrame(model(), kQn);
}

TEST_P(RtbMatlabPuma, Ikine6sSolutionsReachTheSamePose) {
  // ikine6s(fkine(qz), 'ru') and ikine6s(fkine(qn), 'ld'), printed to 4 decimals: forward kinematics at
  // the published solutions must give the poses they were solved for (up to that rounding).
  const Eigen::VectorXd ru = Q({-1.3416, 2.1416, -3.0476, 2.9626, 2.2600, 1.6876});
  const Eigen::VectorXd ld = Q({2.6486, -2.3081, 3.1416, -0.1933, 0.9810, -2.3371});
  EXPECT_LT((model().ForwardKinematics(ru).matrix() - model().ForwardKinematics(kQz).matrix()).cwiseAbs().maxCoeff(),
            2e-4);
  EXPECT_LT((model().ForwardKinematics(ld).matrix() - model().ForwardKinematics(kQn).matrix()).cwiseAbs().maxCoeff(),
            2e-4);
  // Not vacuous: another elbow configuration is far from it.
  EXPECT_GT((model().ForwardKinematics(-ru).matrix() - model().ForwardKinematics(kQz).matrix()).cwiseAbs().maxCoeff(),
            0.1);
}

INSTANTIATE_TEST_SUITE_P(ExampleFiles, RtbMatlabPuma, ::testing::Values("puma560_dh.yaml", "puma560_mdh.yaml"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param).substr(0, std::string(info.param).find('.'));
                         });

// ---- The example robots themselves ----------------------------------------------------------------

TEST(ExampleRobots, PumaInDhAndModifiedDhIsOneArm) {
  const Robot dh = LoadExampleRobot("puma560_dh.yaml");
  const Robot mdh = LoadExampleRobot("puma560_mdh.yaml");
  Rng rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    EXPECT_LT(
        (dh.model().ForwardKinematics(q).matrix() - mdh.model().ForwardKinematics(q).matrix()).cwiseAbs().maxCoeff(),
        1e-15);
    EXPECT_LT((dh.model().JointJacobian(q) - mdh.model().JointJacobian(q)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// Angle between the axes of joints i and j (1-based) at q.
double AxisAngle(const KinematicModel& model, const Eigen::VectorXd& q, int i, int j) {
  const Matrix6Xd J = model.JointJacobian(q);
  return std::acos(std::min(1.0, std::abs(J.col(i - 1).tail<3>().dot(J.col(j - 1).tail<3>()))));
}

TEST(ExampleRobots, ParallelAxesWhereTheMakersHaveThem) {
  const Robot ur10 = LoadExampleRobot("ur10_dh.yaml");
  const Robot irb120 = LoadExampleRobot("irb120_mdh.yaml");
  const Robot seed = testing::SeedNominal();
  Rng rng(2);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    EXPECT_LT(AxisAngle(ur10.model(), q, 2, 3), 1e-7);  // shoulder, elbow, wrist 1: three parallel axes
    EXPECT_LT(AxisAngle(ur10.model(), q, 3, 4), 1e-7);
    EXPECT_LT(AxisAngle(irb120.model(), q, 2, 3), 1e-7);
    for (int i = 1; i < 6; ++i) EXPECT_GT(AxisAngle(seed.model(), q, i, i + 1), 1.0);  // the seed's: none
  }
}

TEST(ExampleRobots, ZeroConfigurationsAsTheMakersDrawThem) {
  // UR10 at q = 0: arm stretched along -x, tool at x = a2 + a3, y = -(d4 + d6), z = d1 - d5.
  const Eigen::Vector3d ur10 =
      LoadExampleRobot("ur10_dh.yaml").model().ForwardKinematics(Eigen::VectorXd::Zero(6)).translation();
  EXPECT_LT((ur10 - Eigen::Vector3d(-0.612 - 0.5723, -0.163941 - 0.0922, 0.1273 - 0.1157)).norm(), 1e-15);
  // IRB 120 at q = 0 (ABB's calibration position): wrist centre at x = 302 mm, z = 290 + 270 + 70 mm;
  // flange 72 mm further along x.
  const Eigen::Vector3d irb =
      LoadExampleRobot("irb120_mdh.yaml").model().ForwardKinematics(Eigen::VectorXd::Zero(6)).translation();
  EXPECT_LT((irb - Eigen::Vector3d(0.374, 0, 0.630)).norm(), 1e-15);
  // Puma 560 at qz, "L shaped": x = a2 + a3, y = -d3 (the shoulder offset), z = d4.
  const Eigen::Vector3d puma =
      LoadExampleRobot("puma560_dh.yaml").model().ForwardKinematics(Eigen::VectorXd::Zero(6)).translation();
  EXPECT_LT((puma - Eigen::Vector3d(0.4318 + 0.0203, -0.15005, 0.4318)).norm(), 1e-15);
}

}  // namespace
}  // namespace kincal
