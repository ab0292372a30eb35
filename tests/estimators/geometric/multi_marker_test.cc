// Several reflectors fitted together, on the protocol of industrial CPA data: one sweep per joint in the
// order 1..6, 6 stops each, the wrist turned 144 deg between stops (288 deg between alternate ones), a
// FANUC-type J2/J3 coupling in the readings, three markers measured at every stop, one of them 1.8 mm
// from the wrist's roll axes. Noise-free data from a known truth must come back exactly: every marker
// predicted at random configurations to rounding level, the axes signed by the readings.
#include <cmath>

#include <gtest/gtest.h>

#include "estimators/geometric/axis_fit.h"
#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "framework/math.h"
#include "framework/random.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::vector<std::string> kMarkers = {"SMR1", "SMR2", "SMR3"};

// The nominal FANUC-type arm with every identifiable parameter moved (lengths by up to 2 mm, angles by up
// to 0.3 deg), other reflector positions and a base elsewhere. alpha_3 moves by 0.05 deg only, and d_2
// stays 0: axes 2 and 3 remain within the parallel threshold, where the identified table puts the
// common normal at the nominal d_2 (common_normals.h), so the truth must be exactly what MDH then holds.
Robot Truth(const Robot& nominal) {
  Robot truth = nominal;
  KinematicModel& model = truth.model();
  Rng rng(11);
  Eigen::VectorXd v = model.Parameters();
  const auto& info = model.parameter_info();
  for (int k = 0; k < model.num_parameters(); ++k) {
    const std::string& name = info[k].name;
    if (name.rfind("tool_", 0) == 0 || name.rfind("base_", 0) == 0 || name == "d_2") continue;
    const bool angle = info[k].kind == ParameterInfo::Kind::kAngle;
    const double size = name == "alpha_3" ? 0.05 * kDeg : angle ? 0.3 * kDeg : 2e-3;
    v[k] += rng.Uniform(-size, size);
  }
  model.SetParameters(v);
  model.SetBase(PoseFromXyzRpy(Eigen::Vector3d(-1.2, -3.5, -0.6), Eigen::Vector3d(0.01, -0.02, 0.4)));
  truth.markers = {{"SMR1", Eigen::Vector3d(-0.5e-3, -1.7e-3, -0.341)},
                   {"SMR2", Eigen::Vector3d(0.196, 0.047, -0.2035)},
                   {"SMR3", Eigen::Vector3d(-0.139, 0.146, -0.203)}};
  return truth;
}

// Readings (deg) of the sweeps, in measurement order, like ../shared/data/fanuc_boby2021: joint 1 from
// q1 = -9, then q1 = 47 for the others; joint 2 swept with q3 = -q2 (the physical joint 3 holds).
std::vector<std::pair<int, Eigen::VectorXd>> Protocol() {
  std::vector<std::pair<int, Eigen::VectorXd>> stops;
  for (int j = 1; j <= 6; ++j) {
    for (int k = 0; k < 6; ++k) {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
      q[0] = 47;
      if (j == 1) q[0] = -9 + 12 * k;
      if (j == 2) q[1] = -30 + 16 * k, q[2] = -q[1];
      if (j == 3) q[2] = -55 + 15 * k;
      if (j == 4) q[3] = -360 + 144 * k;
      if (j == 5) q[4] = -75 + 26 * k;
      if (j == 6) q[5] = -360 + 144 * k;
      stops.emplace_back(j, q * kDeg);
    }
  }
  return stops;
}

// Rows (one per marker and stop; `every` = 2 keeps the 1st, 3rd and 5th stop) measured on `truth`.
Dataset Measure(const Robot& nominal, const Robot& truth, const std::vector<std::pair<int, Eigen::VectorXd>>& stops,
                int every) {
  Dataset data;
  data.dof = 6;
  for (size_t s = 0; s < stops.size(); ++s) {
    if ((s % 6) % every != 0) continue;
    for (const std::string& id : kMarkers) {
      Measurement m;
      m.q = stops[s].second;
      m.sweep = stops[s].first;
      m.marker = id;
      data.rows.push_back(m);
    }
  }
  const std::vector<Eigen::Vector3d> p = PredictMarkers(nominal, truth, data);
  for (size_t r = 0; r < p.size(); ++r) data.rows[r].p = p[r];
  return data;
}

Dataset RandomPoses(const Robot& nominal, const Robot& truth) {
  Rng rng(5);
  std::vector<std::pair<int, Eigen::VectorXd>> stops;
  for (int k = 0; k < 50; ++k) {
    Eigen::VectorXd q(6);
    q << rng.Uniform(-170, 170), rng.Uniform(-60, 70), rng.Uniform(-60, 60), rng.Uniform(-360, 360),
        rng.Uniform(-120, 120), rng.Uniform(-360, 360);
    stops.emplace_back(0, q * kDeg);
  }
  return Measure(nominal, truth, stops, 1);
}

class MultiMarkerSweeps : public ::testing::TestWithParam<int> {};

// Every stop (144 deg wrist steps) and alternate stops (288 deg: shortest-way unwrapping would turn the
// wrist backwards and reverse its axes).
TEST_P(MultiMarkerSweeps, NoiseFreeGiveBackTheTruth) {
  const Robot nominal = LoadExampleRobot("fanuc_r2000_nominal.yaml");
  const Robot truth = Truth(nominal);
  const Dataset data = Measure(nominal, truth, Protocol(), GetParam());
  Robot identified;
  const EstimationReport report = RunPipeline({"geometric"}, {YAML::Load("{}")}, nominal, data, &identified).at(0);
  const PredictionErrors e = EvaluatePredictions(nominal, identified, RandomPoses(nominal, truth));
  std::printf("stops 1/%d: largest error at 150 random marker positions %.3g m\n", GetParam(), e.position_stats.max);
  EXPECT_LT(e.position_stats.max, 1e-9);
  for (const std::string& id : kMarkers) {
    // The markers in the identified tool frame differ from the truth's only through the held d_6 and
    // theta_6 and the kept tool transform; their distances from one another do not.
    EXPECT_NEAR((identified.markers.at(id) - identified.markers.at("SMR2")).norm(),
                (truth.markers.at(id) - truth.markers.at("SMR2")).norm(), 1e-10);
  }
  // The wrist axes point the way their readings turn: angle slopes of +1, not -1.
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(report.details["axes"][j]["angle_slope"].get<double>(), 1.0, 1e-9) << j;
}

INSTANTIATE_TEST_SUITE_P(EveryAndAlternateStops, MultiMarkerSweeps, ::testing::Values(1, 2));

// The joint fit of one axis from three markers: one line, a radius and height per marker, one slope;
// with 20 um of noise it is no worse than the best marker's own fit, and exact without noise.
TEST(AxisFit, SharedAxisOfThreeMarkers) {
  const Eigen::Vector3d c(0.3, -1.2, 0.5), z = Eigen::Vector3d(0.1, -0.3, 1.0).normalized();
  const Eigen::Vector3d u = z.unitOrthogonal(), w = z.cross(u);
  const std::vector<double> radius = {0.0018, 0.21, 0.2}, height = {0.34, 0.2, 0.21}, phase = {0.3, 1.2, 2.9};
  const std::vector<double> x = {-2 * M_PI, -0.4 * M_PI, 1.2 * M_PI};  // 288 deg steps
  for (double noise : {0.0, 20e-6}) {
    Rng rng(3);
    std::vector<std::vector<Eigen::Vector3d>> points(3);
    for (int m = 0; m < 3; ++m) {
      for (double xk : x) {
        const double phi = phase[m] + xk;
        Eigen::Vector3d p = c + height[m] * z + radius[m] * (std::cos(phi) * u + std::sin(phi) * w);
        for (int i = 0; i < 3; ++i) p[i] += noise * rng.Normal();
        points[m].push_back(p);
      }
    }
    const geometric::ArcFit fit = geometric::FitAxis(points, x, geometric::ArcFitOptions());
    const double angle_error = std::acos(std::min(1.0, fit.axis.dot(z)));
    const double offset = ((fit.center - c) - (fit.center - c).dot(z) * z).norm();
    std::printf("noise %.0f um: axis off by %.3g rad, line %.3g m, slope %.9f\n", noise * 1e6, angle_error, offset,
                fit.angle_slope);
    if (noise == 0.0) {
      EXPECT_LT(angle_error, 1e-12);
      EXPECT_LT(offset, 1e-12);
      EXPECT_NEAR(fit.angle_slope, 1.0, 1e-12);
      for (int m = 0; m < 3; ++m) {
        EXPECT_NEAR(fit.circles[m].radius, radius[m], 1e-12);
        EXPECT_LT((fit.MarkerAt(m, x[1]) - points[m][1]).norm(), 1e-12);
      }
    } else {
      EXPECT_LT(angle_error, 1e-3);  // 20 um over 0.2 m
      EXPECT_LT(offset, 1e-4);
      EXPECT_NEAR(fit.angle_slope, 1.0, 1e-3);
    }
  }
}

}  // namespace
}  // namespace kincal::testing
