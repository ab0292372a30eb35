// The joint-space table: interpolation exactness, the choice of joints, exactness at the nodes and the
// documented accuracy on the seed's arm.
#include <gtest/gtest.h>

#include <algorithm>

#include "compensators/jacobian/jacobian_compensator.h"
#include "compensators/joint_space/joint_space_compensator.h"
#include "framework/math.h"
#include "framework/random.h"
#include "tests/compensators/compensator_fixture.h"

namespace kincal {
namespace {

using testing::Arm;
using Interpolation = CorrectionTable::Interpolation;

// A 3-axis table over joints 0, 2, 3 of a 4-joint vector, filled with f at the nodes.
CorrectionTable TableOf(const std::function<double(const Eigen::VectorXd&)>& f, int points) {
  CorrectionTable table({{0, -1.0, 2.0, points}, {2, 0.5, 1.5, points + 1}, {3, -3.0, -1.0, points + 2}}, 1);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4);
  for (int64_t node = 0; node < table.num_nodes(); ++node) {
    table.NodeJoints(node, &q);
    *table.values(node) = f(q);
  }
  return table;
}

TEST(CorrectionTable, MultilinearIsExactForMultilinearFunctions) {
  const auto f = [](const Eigen::VectorXd& q) { return 1 + 2 * q[0] - q[2] + 0.5 * q[0] * q[2] * q[3] + q[3]; };
  const CorrectionTable table = TableOf(f, 4);
  Rng rng(1);
  for (int i = 0; i < 200; ++i) {
    Eigen::VectorXd q(4);
    q << rng.Uniform(-1, 2), 123.0, rng.Uniform(0.5, 1.5), rng.Uniform(-3, -1);  // q[1] is not on the grid
    double value = 0;
    const auto lookup = table.Interpolate(q, Interpolation::kLinear, &value);
    EXPECT_TRUE(lookup.inside);
    EXPECT_NEAR(value, f(q), 1e-13);
  }
}

TEST(CorrectionTable, CubicIsExactForQuadraticsInsideAndLinearAtTheEdges) {
  const auto quadratic = [](const Eigen::VectorXd& q) { return 1 + q[0] * q[0] - 2 * q[2] * q[3] + 0.3 * q[3] * q[3]; };
  const auto linear = [](const Eigen::VectorXd& q) { return 1 + q[0] - 2 * q[2] + 0.3 * q[3]; };
  const CorrectionTable tq = TableOf(quadratic, 6), tl = TableOf(linear, 6);
  Rng rng(2);
  for (int i = 0; i < 200; ++i) {
    Eigen::VectorXd edge(4), inner(4);
    edge << rng.Uniform(-1, 2), 0, rng.Uniform(0.5, 1.5), rng.Uniform(-3, -1);
    // Cells with a neighbour on each side along every axis: [-0.4, 1.4] x [0.67, 1.33] x [-2.71, -1.29].
    inner << rng.Uniform(-0.4, 1.4), 0, rng.Uniform(0.7, 1.3), rng.Uniform(-2.7, -1.3);
    double v = 0;
    tl.Interpolate(edge, Interpolation::kCubic, &v);
    EXPECT_NEAR(v, linear(edge), 1e-12);
    tq.Interpolate(inner, Interpolation::kCubic, &v);
    EXPECT_NEAR(v, quadratic(inner), 1e-12);
  }
}

TEST(CorrectionTable, NodesOutsideAndFlags) {
  CorrectionTable table({{1, -1.0, 1.0, 5}}, 2);
  EXPECT_EQ(table.num_nodes(), 5);
  EXPECT_EQ(table.memory_bytes(), 5u * (2 * sizeof(double) + 1));
  EXPECT_EQ(CorrectionTable::MemoryBytes(table.axes(), 2), 5.0 * (2 * sizeof(double) + 1));
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2);
  table.NodeJoints(4, &q);
  EXPECT_EQ(q[1], 1.0);  // the last node is exactly the upper limit
  for (int64_t node = 0; node < 5; ++node) table.values(node)[0] = table.values(node)[1] = static_cast<double>(node);
  table.Flag(3);
  double v[2];
  q[1] = -0.9;  // cell 0-1
  auto lookup = table.Interpolate(q, Interpolation::kLinear, v);
  EXPECT_TRUE(lookup.inside);
  EXPECT_FALSE(lookup.flagged);
  EXPECT_NEAR(v[0], 0.2, 1e-15);
  q[1] = 0.7;  // cell 3-4
  EXPECT_TRUE(table.Interpolate(q, Interpolation::kLinear, v).flagged);
  q[1] = 1.5;
  lookup = table.Interpolate(q, Interpolation::kLinear, v);
  EXPECT_FALSE(lookup.inside);
  EXPECT_EQ(v[0], 4.0);  // clamped to the edge
  EXPECT_THROW(CorrectionTable({{0, 0.0, 1.0, 1}}, 1), std::invalid_argument);
}

// The seed arm's table at 8 points per joint (TestOptions).
const JointSpaceCompensator& SeedTable() {
  return dynamic_cast<const JointSpaceCompensator&>(testing::Prepared("joint_space"));
}
constexpr int kPoints = 8;

// For the seed's arm the correction does not depend on joints 1 and 6 (base and first row differ by a
// rotation about axis 1 only; both robots carry the same tool after joint 6): a 4-D table over 2..5.
TEST(JointSpace, ChoosesTheJointsThatMatter) {
  const auto& info = SeedTable().table_info();
  EXPECT_EQ(info.joints, (std::vector<int>{2, 3, 4, 5}));
  EXPECT_EQ(info.nodes, kPoints * kPoints * kPoints * kPoints);
  EXPECT_EQ(info.memory_bytes, static_cast<size_t>(info.nodes) * (6 * sizeof(double) + 1));
  JacobianCompensator exact;
  exact.Prepare(Arm().nominal, Arm().identified);
  const auto correction = [&](const Eigen::VectorXd& q) {
    CompensationTarget t;
    t.T_meas_tool = Arm().nominal.model().ForwardKinematics(q);
    t.seed = q;
    return Eigen::VectorXd(exact.Compensate(t).q_actual - q);
  };
  for (const Eigen::VectorXd& q : testing::WellConditionedTargets(5, 31).q_true) {
    Eigen::VectorXd moved = q;
    moved[0] += 1.0;
    moved[5] -= 2.0;
    EXPECT_LE((correction(q) - correction(moved)).cwiseAbs().maxCoeff(), 1e-10);
  }
}

TEST(JointSpace, AToolChangeBringsTheLastJointIn) {
  Robot identified = Arm().identified;
  identified.model().SetParameter("tool_x", identified.model().Parameter("tool_x") + 0.001);
  JointSpaceCompensator::Options o;
  o.points = 3;
  JointSpaceCompensator c(o);
  c.Prepare(Arm().nominal, identified);
  EXPECT_EQ(c.table_info().joints, (std::vector<int>{2, 3, 4, 5, 6}));
}

// At the nodes the table holds the exact correction (whatever joints 1 and 6 are).
TEST(JointSpace, ExactAtTheNodes) {
  const JointSpaceCompensator& c = SeedTable();
  Rng rng(3);
  int checked = 0;
  for (int i = 0; i < 40; ++i) {
    Eigen::VectorXd q(6);
    q[0] = rng.Uniform(-2, 2);
    q[5] = rng.Uniform(-2, 2);
    for (int j = 1; j <= 4; ++j) {
      const auto [low, high] = Arm().nominal.Limit(j);
      const int k = static_cast<int>(rng.Uniform(0, kPoints));
      q[j] = low + k * (high - low) / (kPoints - 1);
    }
    CompensationTarget t;
    t.T_meas_tool = Arm().nominal.model().ForwardKinematics(q);
    t.seed = q;
    const CompensationResult r = c.Compensate(t);
    if (r.report.status != CompensationStatus::kConverged) continue;  // a flagged node
    ++checked;
    EXPECT_LE(r.report.position_error, 1e-9);
    EXPECT_LE(r.report.orientation_error, 1e-9);
  }
  EXPECT_GE(checked, 10);
}

TEST(JointSpaceOptions, FromYamlAndValidation) {
  const auto o = JointSpaceCompensator::Options::FromYaml(
      YAML::Load("{joints: [2, 3], points: 9, interpolation: cubic, max_correction: 0.2}"));
  EXPECT_EQ(o.joints, (std::vector<int>{2, 3}));
  EXPECT_EQ(o.points, 9);
  EXPECT_EQ(o.interpolation, "cubic");
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  EXPECT_TRUE(JointSpaceCompensator::Options::FromYaml(YAML::Load("{joints: auto}")).joints.empty());
  EXPECT_THROW(JointSpaceCompensator::Options::FromYaml(YAML::Load("{joints: [two]}")), std::invalid_argument);
  JointSpaceCompensator::Options bad;
  bad.interpolation = "spline";
  EXPECT_FALSE(bad.IsValid(&why));
  bad = JointSpaceCompensator::Options();
  bad.joints = {2, 2};
  EXPECT_FALSE(bad.IsValid(&why));
  // A table that would not fit is refused before it is built.
  JointSpaceCompensator::Options huge;
  huge.joints = {1, 2, 3, 4, 5, 6};
  huge.points = 100;
  JointSpaceCompensator c(huge);
  EXPECT_THROW(c.Prepare(Arm().nominal, Arm().identified), std::invalid_argument);
  // So is a joint the robot does not have.
  JointSpaceCompensator::Options seven;
  seven.joints = {7};
  JointSpaceCompensator c7(seven);
  EXPECT_THROW(c7.Prepare(Arm().nominal, Arm().identified), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
