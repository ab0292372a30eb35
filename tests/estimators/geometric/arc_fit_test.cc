// Plane fit, axis from an arc (sign, angles), and the arc fit's refusals.
#include "estimators/geometric/arc_fit.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "estimators/geometric/plane_fit.h"
#include "framework/random.h"

namespace kincal::geometric {
namespace {

// A marker at radius r about the axis (c, z), turned to angle phi0 + s * x for each drive value x.
std::vector<Eigen::Vector3d> Stops(const Eigen::Vector3d& c, const Eigen::Vector3d& z, double r, double phi0, double s,
                                   const std::vector<double>& x) {
  const Eigen::Vector3d u = z.unitOrthogonal(), v = z.cross(u);
  std::vector<Eigen::Vector3d> p;
  for (double xi : x) p.push_back(c + r * (std::cos(phi0 + s * xi) * u + std::sin(phi0 + s * xi) * v));
  return p;
}

std::vector<double> Steps(int count, double step) {
  std::vector<double> x;
  for (int k = 0; k < count; ++k) x.push_back(k * step);
  return x;
}

TEST(PlaneFit, NormalOfPointsOnAPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  std::vector<Eigen::Vector3d> p;
  Rng rng(2);
  for (int k = 0; k < 10; ++k) {
    const Eigen::Vector3d q(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    p.push_back(q - q.dot(n) * n + 0.7 * n);
  }
  const PlaneFit plane = FitPlane(p);
  EXPECT_NEAR(std::abs(plane.normal.dot(n)), 1.0, 1e-15);
  EXPECT_NEAR(plane.spread[2], 0.0, 1e-15);
  EXPECT_NEAR(plane.centroid.dot(n), 0.7, 1e-15);
  EXPECT_NEAR(plane.e1.cross(plane.e2).dot(plane.normal), 1.0, 1e-15);
}

TEST(ArcFit, AxisSignedByTheDirectionOfRotation) {
  const Eigen::Vector3d c(0.4, -0.2, 0.9), z = Eigen::Vector3d(0.2, 0.1, -1.0).normalized();
  const std::vector<double> x = Steps(20, 2 * M_PI / 180);
  // The joint turns positively about z as x grows (slope 0.996: a ratio error of 0.4 %).
  ArcFit fit = FitArc(Stops(c, z, 0.3, 1.0, 0.996, x), x, ArcFitOptions());
  EXPECT_NEAR(fit.axis.dot(z), 1.0, 1e-14);
  EXPECT_NEAR((fit.center - c).norm(), 0.0, 1e-13);
  EXPECT_NEAR(fit.radius, 0.3, 1e-14);
  EXPECT_NEAR(fit.angle_slope, 0.996, 1e-12);
  EXPECT_NEAR(fit.arc, 0.996 * 38 * M_PI / 180, 1e-12);
  EXPECT_NEAR(fit.e1.cross(fit.e2).dot(fit.axis), 1.0, 1e-15);
  for (size_t k = 0; k < x.size(); ++k) {
    EXPECT_NEAR((fit.PointAtAngle(fit.AngleAt(x[k])) - Stops(c, z, 0.3, 1.0, 0.996, {x[k]})[0]).norm(), 0.0, 1e-13);
  }
  // Turning the other way about z as x grows: the axis is -z. Row order does not matter.
  std::vector<double> reversed(x.rbegin(), x.rend());
  fit = FitArc(Stops(c, z, 0.3, 1.0, -0.996, reversed), reversed, ArcFitOptions());
  EXPECT_NEAR(fit.axis.dot(z), -1.0, 1e-14);
  EXPECT_NEAR(fit.angle_slope, 0.996, 1e-12);
}

TEST(ArcFit, UnwrapsArcsBeyondHalfATurn) {
  const std::vector<double> x = Steps(36, 10 * M_PI / 180);  // 350 deg
  const ArcFit fit = FitArc(Stops({0, 0, 0}, {0, 0, 1}, 0.2, 3.0, 1.0, x), x, ArcFitOptions());
  EXPECT_NEAR(fit.arc, 350 * M_PI / 180, 1e-12);
  EXPECT_NEAR(fit.angle_slope, 1.0, 1e-12);
}

// Stops more than half a turn apart (a wrist swept -360, -72, 216 deg): the shortest way between the
// in-plane directions runs backwards (-72 deg per step), which reversed the axis; the readings' steps
// decide the turn, in either row order and whichever way the joint turns.
TEST(ArcFit, StepsBeyondHalfATurnFollowTheReadings) {
  const Eigen::Vector3d c(0.1, -0.3, 0.6), z = Eigen::Vector3d(-0.97, -0.23, 0.01).normalized();
  for (const std::vector<double>& x : {std::vector<double>{-2 * M_PI, -0.4 * M_PI, 1.2 * M_PI},
                                       std::vector<double>{1.2 * M_PI, -2 * M_PI, -0.4 * M_PI},
                                       std::vector<double>{-2 * M_PI, -1.2 * M_PI, -0.4 * M_PI, 0.4 * M_PI}}) {
    for (double turn : {1.0, -1.0}) {
      const ArcFit fit = FitArc(Stops(c, z, 0.2, 0.5, turn, x), x, ArcFitOptions());
      EXPECT_NEAR(fit.axis.dot(z), turn, 1e-12);
      EXPECT_NEAR(fit.angle_slope, 1.0, 1e-12);
      for (double xk : x) {
        EXPECT_NEAR((fit.PointAtAngle(fit.AngleAt(xk)) - Stops(c, z, 0.2, 0.5, turn, {xk})[0]).norm(), 0.0, 1e-12);
      }
    }
  }
}

TEST(ArcFit, RefusesDegenerateSweeps) {
  const Eigen::Vector3d c(0, 0, 0), z(0, 0, 1);
  const std::vector<double> x = Steps(20, 2 * M_PI / 180);
  const auto message = [&](const std::vector<Eigen::Vector3d>& p, const std::vector<double>& xs) -> std::string {
    try {
      FitArc(p, xs, ArcFitOptions());
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(Stops(c, z, 0.3, 0, 1, Steps(2, 0.1)), Steps(2, 0.1)).find("at least 3 stops"), std::string::npos);
  EXPECT_NE(message(Stops(c, z, 0.3, 0, 1, x), std::vector<double>(20, 0.5)).find("does not move"), std::string::npos);
  // A marker on the axis: every stop at the same place.
  EXPECT_NE(message(Stops(c, z, 0.0, 0, 1, x), x).find("on the joint's axis"), std::string::npos);
  std::vector<Eigen::Vector3d> line;
  for (double xi : x) line.push_back(Eigen::Vector3d(0.1, 0.2, 0.3) + xi * Eigen::Vector3d(1, -2, 0.5));
  EXPECT_NE(message(line, x).find("straight line"), std::string::npos);
}

// min_curvature_ratio = 2 refuses stops that are a straight line plus noise for most noise draws (the
// curvature it would fit is noise), and accepts the seed's shortest arc (50 mm radius, 38 deg) at 0.1 mm.
TEST(ArcFit, CurvatureGuardSeparatesNoiseFromArcs) {
  const std::vector<double> x = Steps(20, 2 * M_PI / 180);
  int refused = 0;
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    Rng rng(seed);
    std::vector<Eigen::Vector3d> p;
    for (double xi : x) {
      p.push_back(Eigen::Vector3d(xi * 0.05, 0, 0) + 1e-4 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()));
    }
    try {
      FitArc(p, x, ArcFitOptions());
    } catch (const std::invalid_argument&) {
      ++refused;
    }
  }
  EXPECT_GE(refused, 190);
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    Rng rng(seed);
    std::vector<Eigen::Vector3d> p = Stops({0, 0, 0}, {0, 0, 1}, 0.05, 0.0, 1.0, x);
    for (auto& q : p) q += 1e-4 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
    EXPECT_NO_THROW(FitArc(p, x, ArcFitOptions())) << seed;
  }
}

}  // namespace
}  // namespace kincal::geometric
