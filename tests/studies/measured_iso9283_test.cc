// ISO 9283 from measured rows (studies/measured_iso9283.h) on made-up visits whose AP and RP are known.
#include <cmath>

#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "robot/prediction.h"
#include "studies/measured_iso9283.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::VectorXd Q(std::initializer_list<double> deg) {
  Eigen::VectorXd q(deg.size());
  int i = 0;
  for (double d : deg) q[i++] = d * kDeg;
  return q;
}

// Three commanded poses visited in turns (A B C A B C ...) and a fourth once; each visit of pose k is
// measured at the model's pose shifted by offset[k] plus a known scatter along x (+e, -e, +e, -e).
struct Visits {
  Robot robot = SeedNominal();
  Dataset data;
  std::vector<Eigen::Vector3d> offset = {{0.3e-3, 0, 0}, {0, -0.2e-3, 0.1e-3}, {0, 0, 0}};
  double e = 10e-6;
  Visits(bool orientation) {
    data.dof = 6;
    const std::vector<Eigen::VectorXd> poses = {Q({10, 20, 30, 0, 40, 0}), Q({-20, 10, 40, 10, 30, 5}),
                                                Q({30, 40, 10, -10, 50, 20})};
    for (int cycle = 0; cycle < 4; ++cycle) {
      for (int k = 0; k < 3; ++k) {
        Measurement m;
        m.q = poses[k];
        const Eigen::Isometry3d T = PredictToolPose(robot, m.q);
        m.p = T.translation() + offset[k] + Eigen::Vector3d((cycle % 2 == 0 ? 1 : -1) * e, 0, 0);
        if (orientation) m.orientation = Eigen::Quaterniond(T.linear());
        data.rows.push_back(m);
      }
    }
    Measurement once;
    once.q = Q({0, 30, 30, 0, 30, 0});
    once.p = PredictToolPose(robot, once.q).translation();
    if (orientation) once.orientation = Eigen::Quaterniond(PredictToolPose(robot, once.q).linear());
    data.rows.push_back(once);
  }
};

TEST(MeasuredIso9283, KnownAccuracyAndRepeatability) {
  const Visits v(true);
  const std::vector<MeasuredIsoPose> poses = MeasuredIso9283(v.robot, v.robot, v.data, VisitTolerance(), 2);
  ASSERT_EQ(poses.size(), 3u);  // the pose visited once is not scored
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(poses[k].pose, k + 1);
    EXPECT_EQ(poses[k].rows, (std::vector<int>{k, k + 3, k + 6, k + 9}));
    EXPECT_EQ(poses[k].stats.cycles, 4);
    // The scatter averages out: AP is the offset; every visit lies e from the barycentre: RP = e + 3 * 0.
    EXPECT_NEAR(poses[k].stats.ap_p, v.offset[k].norm(), 1e-12);
    EXPECT_NEAR(poses[k].stats.rp_l, v.e, 1e-12);
    EXPECT_LT(poses[k].stats.ap_abc.norm(), 1e-12);
    EXPECT_LT(poses[k].stats.rp_abc.norm(), 1e-12);
  }
}

TEST(MeasuredIso9283, WithoutOrientationTheAnglesAreNaN) {
  const Visits v(false);
  const std::vector<MeasuredIsoPose> poses = MeasuredIso9283(v.robot, v.robot, v.data, VisitTolerance(), 4);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_NEAR(poses[1].stats.ap_p, v.offset[1].norm(), 1e-12);
  EXPECT_TRUE(std::isnan(poses[1].stats.ap_abc[0]));
  EXPECT_TRUE(std::isnan(poses[1].stats.rp_abc[2]));
  // More cycles asked for than any pose has: nothing scored.
  EXPECT_TRUE(MeasuredIso9283(v.robot, v.robot, v.data, VisitTolerance(), 5).empty());
}

TEST(MeasuredIso9283, VisitsAreCommandedPosesWithinTheTolerance) {
  Visits v(false);
  // A visit whose joints put the tool 0.5 mm from the pose's first visit is another commanded pose; one
  // 0.05 mm away is the same pose (tolerance 0.2 mm).
  const Matrix6Xd J = v.robot.model().JointJacobian(v.data.rows[0].q);
  const Eigen::VectorXd step = J.topRows<3>().completeOrthogonalDecomposition().solve(Eigen::Vector3d(1e-3, 0, 0));
  Dataset data = v.data;
  data.rows[3].q = data.rows[0].q + 0.5 * step;
  data.rows[6].q = data.rows[0].q + 0.05 * step;
  const auto groups = GroupVisits(v.robot, data, VisitTolerance());
  ASSERT_EQ(groups.size(), 5u);  // A (3 visits), B, C, the moved visit of A, the single pose
  EXPECT_EQ(groups[0], (std::vector<int>{0, 6, 9}));
  EXPECT_EQ(groups[3], (std::vector<int>{3}));
  // A session of its own is another frame: never the same pose.
  data.rows[9].session = 2;
  EXPECT_EQ(GroupVisits(v.robot, data, VisitTolerance())[0], (std::vector<int>{0, 6}));
}

}  // namespace
}  // namespace kincal::testing
