// Closed-form fixture starts: a sphere, a plane and a centroid recover a known fixture from positions
// that satisfy it exactly, and to the scatter from noisy ones; StartFixtures adds what the data names.
#include <gtest/gtest.h>

#include "framework/random.h"
#include "robot/fixture_fits.h"
#include "robot/prediction.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(Rng& rng, int count, double flatness = 1.0) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i)
    points.emplace_back(rng.Uniform(-0.4, 0.4), rng.Uniform(-0.4, 0.4), flatness * rng.Uniform(-0.4, 0.4));
  return points;
}

TEST(FixtureFits, SphereCentreFromExactDistances) {
  Rng rng(3);
  const Eigen::Vector3d pivot(0.7, 0.1, 0.3);
  const std::vector<Eigen::Vector3d> points = RandomPoints(rng, 30);
  std::vector<double> d;
  for (const auto& p : points) d.push_back((p - pivot).norm());
  EXPECT_LT((FitSphereCentre(points, d) - pivot).norm(), 1e-10);
}

TEST(FixtureFits, SphereCentreWithNoiseIsNearTheTruthAndBeatsTheLinearStart) {
  Rng rng(4);
  const Eigen::Vector3d pivot(-0.2, 0.7, 0.1);
  const std::vector<Eigen::Vector3d> points = RandomPoints(rng, 200);
  std::vector<double> d;
  for (const auto& p : points) d.push_back((p - pivot).norm() + 1e-4 * rng.Normal());
  const Eigen::Vector3d c = FitSphereCentre(points, d);
  EXPECT_LT((c - pivot).norm(), 1e-4);
  // The refined centre is a minimum: no neighbour 10 um away does better.
  const auto cost = [&](const Eigen::Vector3d& x) {
    double s = 0.0;
    for (size_t i = 0; i < points.size(); ++i) s += std::pow((points[i] - x).norm() - d[i], 2);
    return s;
  };
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = 1e-5 * Eigen::Vector3d::Unit(k);
    EXPECT_LE(cost(c), cost(c + e));
    EXPECT_LE(cost(c), cost(c - e));
  }
}

TEST(FixtureFits, SphereCentreFromPositionsOnOnePlaneTakesTheSideOfTheHint) {
  Rng rng(5);
  const Eigen::Vector3d pivot(0.1, 0.2, 0.5);
  const std::vector<Eigen::Vector3d> points = RandomPoints(rng, 40, 0.0);  // all at z = 0
  std::vector<double> d;
  for (const auto& p : points) d.push_back((p - pivot).norm());
  const Eigen::Vector3d up(0, 0, 1), down(0, 0, -1);
  EXPECT_LT((FitSphereCentre(points, d, &up) - pivot).norm(), 1e-9);
  const Eigen::Vector3d mirror(pivot.x(), pivot.y(), -pivot.z());
  EXPECT_LT((FitSphereCentre(points, d, &down) - mirror).norm(), 1e-9);
}

TEST(FixtureFits, PlaneAndCentroid) {
  Rng rng(6);
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 0.9).normalized();
  const double offset = 0.25;
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : RandomPoints(rng, 50)) points.push_back(p - normal * (normal.dot(p) - offset));
  const PlaneFit fit = FitPlane(points);
  EXPECT_LT((fit.normal - normal).norm(), 1e-12);
  EXPECT_NEAR(fit.offset, offset, 1e-12);
  // The same plane given the other way round comes out the same (offset >= 0).
  std::vector<Eigen::Vector3d> reversed(points.rbegin(), points.rend());
  EXPECT_LT((FitPlane(reversed).normal - normal).norm(), 1e-12);
  EXPECT_LT((Centroid({Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(3, 2, 1)}) - Eigen::Vector3d(2, 2, 2)).norm(), 1e-15);
}

TEST(FixtureFits, TooFewOrDegeneratePositionsAreRefused) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_THROW(FitSphereCentre(line, {1, 1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(FitSphereCentre({{0, 0, 0}}, {1}), std::invalid_argument);
  EXPECT_THROW(FitPlane(line), std::invalid_argument);
  EXPECT_THROW(Centroid({}), std::invalid_argument);
}

// Rows of every fixture kind on the truth arm: each unknown fixture starts where it is.
TEST(FixtureFits, StartFixturesAddsWhatTheDataNamesAtItsClosedForm) {
  const Robot robot = testing::SeedNominal();
  Rng rng(8);
  Dataset data;
  data.dof = robot.dof();
  const Eigen::Vector3d pivot(0.5, 0.3, 0.2), socket(0.4, -0.1, 0.3);
  for (int i = 0; i < 40; ++i) {
    Measurement m;
    m.q = Eigen::VectorXd(robot.dof());
    for (int j = 0; j < robot.dof(); ++j) m.q[j] = rng.Uniform(-1.0, 1.0);
    data.rows.push_back(m);
  }
  const std::vector<Eigen::Vector3d> p = PredictMarkers(robot, robot, data);
  for (size_t i = 0; i < data.rows.size(); ++i) {
    Measurement& m = data.rows[i];
    m.kind = i % 2 ? MeasurementKind::kDistance : MeasurementKind::kPlane;
    m.fixture = i % 2 ? "P" : "table";
    m.distance = (p[i] - pivot).norm();
  }
  Robot start = robot;
  start.fixtures.items.push_back({Fixture::Type::kPoint, "socket", socket, {0, 0, 1}, 0.0, 0.0, 0.0, true});
  const Fixtures f = StartFixtures(robot, start, data);
  ASSERT_EQ(f.items.size(), 3u);
  EXPECT_EQ(f.Find(Fixture::Type::kPoint, "socket")->position, socket);  // given: kept as it is
  const Fixture* P = f.Find(Fixture::Type::kPivot, "P");
  ASSERT_NE(P, nullptr);
  EXPECT_FALSE(P->known);
  EXPECT_LT((P->position - pivot).norm(), 1e-9);
  // Random configurations are not on a plane: the start is the least-squares plane of the same positions.
  std::vector<Eigen::Vector3d> even;
  for (size_t i = 0; i < p.size(); i += 2) even.push_back(p[i]);
  const Fixture* table = f.Find(Fixture::Type::kPlane, "table");
  ASSERT_NE(table, nullptr);
  EXPECT_LT((table->normal - FitPlane(even).normal).norm(), 1e-12);
}

}  // namespace
}  // namespace kincal
