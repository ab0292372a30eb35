// MDH rows from frames, frames from axes by common normals (with the parallel convention), and the exact
// DH -> MDH conversion.
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "estimators/geometric/common_normals.h"
#include "models/conversion.h"
#include "estimators/geometric/mdh_from_frames.h"
#include "framework/math.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "tests/support/test_util.h"

namespace kincal::geometric {
namespace {

std::vector<MdhRow> Rows(const KinematicModel& model) {
  std::vector<MdhRow> rows;
  for (int i = 1; i <= model.dof(); ++i) {
    const std::string s = "_" + std::to_string(i);
    rows.push_back({model.Parameter("alpha" + s), model.Parameter("a" + s), model.Parameter("theta" + s),
                    model.Parameter("d" + s)});
  }
  return rows;
}

TEST(MdhFromFrames, RowsRoundTripThroughFrames) {
  Rng rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const MdhRow row{rng.Uniform(-3.1, 3.1), rng.Uniform(-1, 1), rng.Uniform(-3.1, 3.1), rng.Uniform(-1, 1)};
    const double q = rng.Uniform(-3, 3);
    const Eigen::Isometry3d T_meas_prev =
        PoseFromXyzRpy({rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)},
                       {rng.Uniform(-3, 3), rng.Uniform(-1.5, 1.5), rng.Uniform(-3, 3)});
    const MdhRow back = MdhRowFromFrames(T_meas_prev, T_meas_prev * MdhTransform(row, q), q);
    EXPECT_NEAR(back.alpha, row.alpha, 1e-13);
    EXPECT_NEAR(back.a, row.a, 1e-14);
    EXPECT_NEAR(WrapAngle(back.theta - row.theta), 0.0, 1e-13);
    EXPECT_NEAR(back.d, row.d, 1e-14);
  }
}

// The truth arm's own axes (each given by an arbitrary point on it) give back its frames exactly, with
// the x signs of the nominal (alpha_4 = alpha_6 = -90 deg keep their sign).
TEST(CommonNormals, AxesOfAnMdhArmGiveBackItsFrames) {
  const Robot truth = testing::SeedTruth();
  const Robot nominal = testing::SeedNominal();
  const Eigen::VectorXd q = (Eigen::VectorXd(6) << 0.1, -0.2, 0.3, 0.4, -0.5, 0.6).finished();
  const std::vector<Eigen::Isometry3d> F = truth.model().FramePoses(q);
  std::vector<AxisLine> axes;
  for (int i = 1; i <= 6; ++i) {
    const Eigen::Vector3d z = F[i].linear().col(2);
    axes.push_back({F[i].translation() + (0.37 * i - 1.0) * z, z});
  }
  const AxisFrames frames = FramesFromAxes(axes, Rows(nominal.model()), q, F[1].linear().col(0), 1 * M_PI / 180);
  for (int i = 1; i <= 6; ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR((frames.frames[i - 1].translation() - F[i].translation()).norm(), 0.0, 1e-13);
    EXPECT_NEAR((frames.frames[i - 1].linear() - F[i].linear()).norm(), 0.0, 1e-13);
  }
  for (const auto& pair : frames.pairs) EXPECT_FALSE(pair.parallel);
}

// UR10-like arm: axes 2, 3, 4 parallel. A noise-like tilt of axis 3 about y_2 (which MDH cannot hold)
// puts the common perpendicular's foot about a / tilt = 0.61 m / 1e-4 = 6 km away; the convention keeps
// every origin near the arm, drops that tilt (and reports it), and keeps the tilt about x_2 (alpha_3).
TEST(CommonNormals, ParallelAxesGiveBoundedFramesAndReportTheDroppedTilt) {
  const Robot ur10 = ParseRobotYaml(R"(
name: ur10
convention: dh
units: {length: m, angle: rad}
joints:
  - {theta: 0, d: 0.1273, a: 0, alpha: 1.5707963267948966}
  - {theta: 0, d: 0, a: -0.612, alpha: 0}
  - {theta: 0, d: 0, a: -0.5723, alpha: 0}
  - {theta: 0, d: 0.163941, a: 0, alpha: 1.5707963267948966}
  - {theta: 0, d: 0.1157, a: 0, alpha: -1.5707963267948966}
  - {theta: 0, d: 0.0922, a: 0, alpha: 0}
)",
                                    "ur10");
  const Robot mdh = ur10.WithModel(ConvertModel(ur10.model(), "mdh"));
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  const std::vector<Eigen::Isometry3d> F = mdh.model().FramePoses(q);
  std::vector<AxisLine> axes;
  for (int i = 1; i <= 6; ++i) axes.push_back({F[i].translation(), F[i].linear().col(2)});
  // Axis 3 tilted by 1e-4 rad about y_2 and 2e-4 rad about x_2.
  const Eigen::Vector3d x2 = F[2].linear().col(0), y2 = F[2].linear().col(1);
  axes[2].direction = (Eigen::AngleAxisd(2e-4, x2) * Eigen::AngleAxisd(1e-4, y2) * axes[2].direction).normalized();
  const AxisFrames frames = FramesFromAxes(axes, Rows(mdh.model()), q, F[1].linear().col(0), 1 * M_PI / 180);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(frames.frames[i].matrix().allFinite());
    EXPECT_LT((frames.frames[i].translation() - F[i + 1].translation()).norm(), 1e-3) << "frame " << i + 1;
  }
  ASSERT_EQ(frames.pairs.size(), 5u);
  EXPECT_TRUE(frames.pairs[1].parallel);  // axes 2, 3
  EXPECT_TRUE(frames.pairs[2].parallel);  // axes 3, 4
  EXPECT_FALSE(frames.pairs[0].parallel);
  EXPECT_NEAR(std::abs(frames.pairs[1].dropped_tilt), 1e-4, 1e-8);
  const MdhRow row3 = MdhRowFromFrames(frames.frames[1], frames.frames[2], 0.0);
  EXPECT_NEAR(std::abs(row3.alpha), 2e-4, 1e-8);
  EXPECT_NEAR(row3.a, -0.612, 1e-6);
  EXPECT_NEAR(row3.d, 0.0, 1e-6);
  // Without the convention (threshold 0) the exact common perpendicular's foot is kilometres away.
  const AxisFrames exact = FramesFromAxes(axes, Rows(mdh.model()), q, F[1].linear().col(0), 0.0);
  EXPECT_GT((exact.frames[1].translation() - F[2].translation()).norm(), 1e3);
}

TEST(MdhConversion, DhRobotHasTheSameForwardKinematics) {
  const Robot dh = ParseRobotYaml(R"(
name: arm
convention: dh
units: {length: m, angle: deg}
joints:
  - {theta: 10, d: 0.3, a: 0.05, alpha: 90}
  - {theta: -20, d: 0.02, a: 0.3, alpha: -85}
  - {theta: 5, d: 0.25, a: 0.02, alpha: 95}
  - {theta: 0, d: 0.3, a: 0.01, alpha: -90}
base: {xyz: [0.1, -0.2, 0.3], rpy: [10, 20, 30]}
tool: {xyz: [0.04, 0.03, 0.1], rpy: [-5, 15, 25]}
)",
                                  "arm");
  const Robot mdh = dh.WithModel(ConvertModel(dh.model(), "mdh"));
  EXPECT_EQ(mdh.model().convention(), "mdh");
  Rng rng(8);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(4);
    for (int i = 0; i < 4; ++i) q[i] = rng.Uniform(-3, 3);
    const Eigen::Isometry3d a = dh.model().ForwardKinematics(q), b = mdh.model().ForwardKinematics(q);
    EXPECT_NEAR((a.matrix() - b.matrix()).norm(), 0.0, 1e-14);
  }
}

}  // namespace
}  // namespace kincal::geometric
