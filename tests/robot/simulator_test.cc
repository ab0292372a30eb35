// The simulator's physics: what a tracker would measure on the truth robot when a controller that
// believes the nominal ratios commands it (METHOD.md sections 2 and 3).
#include <cmath>

#include <gtest/gtest.h>

#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::SeedNominal;
using testing::SeedTruth;

SimulatorOptions Random(int poses, uint64_t seed) {
  SimulatorOptions o;
  o.protocol = "random";
  o.poses = poses;
  o.seed = seed;
  return o;
}

TEST(Simulator, NoiseFreeDataIsTheTruthAtTheActualJointAngles) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  const Dataset data = Simulate(nominal, truth, Random(200, 7));
  ASSERT_EQ(data.rows.size(), 200u);
  const DriveModel& controller = *nominal.drives;
  const DriveModel& real = *truth.drives;
  double largest_ratio_effect = 0.0;
  for (const Measurement& m : data.rows) {
    ASSERT_EQ(m.encoders.size(), 6u);
    Eigen::VectorXd q_actual(6);
    for (int j = 0; j < 6; ++j) {
      // The controller turns the commanded angle into the nearest whole count with ITS ratio ...
      const double exact_counts = controller.counts_per_rev[j] * controller.ratio[j] * m.q[j] / (2 * M_PI);
      EXPECT_EQ(m.encoders[j], std::llround(exact_counts));
      EXPECT_LE(std::abs(m.encoders[j] - exact_counts), 0.5);
      // ... and the joint goes wherever those counts put it with the REAL ratio: q = counts 2 pi / (C K).
      q_actual[j] = static_cast<double>(m.encoders[j]) * 2 * M_PI / (real.counts_per_rev[j] * real.ratio[j]);
      // Within one count of q_cmd * K_nominal / K_true.
      const double one_count = 2 * M_PI / (real.counts_per_rev[j] * real.ratio[j]);
      EXPECT_LE(std::abs(q_actual[j] - m.q[j] * controller.ratio[j] / real.ratio[j]), 0.5 * one_count + 1e-15);
    }
    const Eigen::Vector3d expected = truth.model().ForwardKinematics(q_actual).translation();
    EXPECT_LT((m.p - expected).norm(), 1e-12);
    largest_ratio_effect =
        std::max(largest_ratio_effect, (truth.model().ForwardKinematics(m.q).translation() - m.p).norm());
  }
  // The ratio error is visible: the truth at the commanded angles is millimetres off.
  EXPECT_GT(largest_ratio_effect, 1e-3);
}

TEST(Simulator, WithoutDrivesTheJointsGoWhereCommanded) {
  Robot nominal = SeedNominal(), truth = SeedTruth();
  nominal.drives.reset();
  truth.drives.reset();
  const Dataset data = Simulate(nominal, truth, Random(20, 3));
  for (const Measurement& m : data.rows) {
    EXPECT_TRUE(m.encoders.empty());
    EXPECT_EQ(m.p, truth.model().ForwardKinematics(m.q).translation());
  }
  Robot only_one = SeedNominal();
  EXPECT_THROW(Simulate(only_one, truth, Random(1, 1)), std::invalid_argument);
}

TEST(Simulator, EveryMarkerIsRecordedAtEveryPose) {
  const Robot nominal = SeedNominal();
  Robot truth = SeedTruth();
  truth.markers["A"] = Eigen::Vector3d(0.05, 0.0, 0.1);
  truth.markers["B"] = Eigen::Vector3d(-0.05, 0.02, 0.1);
  const Dataset data = Simulate(nominal, truth, Random(10, 5));
  ASSERT_EQ(data.rows.size(), 20u);
  for (size_t r = 0; r < data.rows.size(); r += 2) {
    EXPECT_EQ(data.rows[r].marker, "A");
    EXPECT_EQ(data.rows[r + 1].marker, "B");
    EXPECT_EQ(data.rows[r].q, data.rows[r + 1].q);
    const Eigen::Isometry3d T = truth.model().ForwardKinematics(
        DriveModel::ActualFromCommanded(*nominal.drives, *truth.drives, data.rows[r].q));
    EXPECT_LT((data.rows[r].p - T * truth.markers["A"]).norm(), 1e-6);  // within the encoder rounding
    EXPECT_LT((data.rows[r + 1].p - T * truth.markers["B"]).norm(), 1e-6);
  }
  SimulatorOptions unknown = Random(1, 1);
  unknown.markers = {"C"};
  EXPECT_THROW(Simulate(nominal, truth, unknown), std::invalid_argument);
}

TEST(Simulator, SweepProtocolSweepsJointsNDownToOneAndLeavesEachWhereItEnded) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  SimulatorOptions o;  // the seed's protocol: 20 stops, 2 degrees apart, from q = 0
  const Dataset data = Simulate(nominal, truth, o);
  ASSERT_EQ(data.rows.size(), 120u);
  const double step = 2.0 * M_PI / 180.0;
  for (int r = 0; r < 120; ++r) {
    const int block = r / 20, stop = r % 20;
    const int swept = 6 - block;  // 6, 5, ..., 1
    EXPECT_EQ(data.rows[r].sweep, swept);
    for (int j = 1; j <= 6; ++j) {
      double expected = 0.0;  // not swept yet: still at the start
      if (j == swept)
        expected = stop * step;  // being swept
      else if (j > swept)
        expected = 19 * step;  // swept before: stays where its sweep ended
      EXPECT_EQ(data.rows[r].q[j - 1], expected) << "row " << r << ", joint " << j;
    }
  }
}

TEST(Simulator, SweepFromAStartConfigurationInAGivenOrder) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  SimulatorOptions o;
  o.start = Eigen::VectorXd::LinSpaced(6, 0.1, 0.6);
  o.sweep_order = {2, 5};
  o.stops = 3;
  o.step = -0.01;
  const Dataset data = Simulate(nominal, truth, o);
  ASSERT_EQ(data.rows.size(), 6u);
  Eigen::VectorXd q = o.start;
  for (int r = 0; r < 3; ++r) {
    q[1] = o.start[1] + r * o.step;
    EXPECT_EQ(data.rows[r].q, q);
    EXPECT_EQ(data.rows[r].sweep, 2);
  }
  for (int r = 0; r < 3; ++r) {
    q[4] = o.start[4] + r * o.step;
    EXPECT_EQ(data.rows[3 + r].q, q);  // joint 2 holds o.start[1] + 2 step
    EXPECT_EQ(data.rows[3 + r].sweep, 5);
  }
  o.sweep_order = {7};
  EXPECT_THROW(Simulate(nominal, truth, o), std::invalid_argument);
}

TEST(Simulator, RandomProtocolStaysWithinTheLimitsAndCoversThem) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  const Dataset data = Simulate(nominal, truth, Random(2000, 11));
  for (int j = 0; j < 6; ++j) {
    const auto [low, high] = nominal.Limit(j);
    double smallest = high, largest = low;
    for (const Measurement& m : data.rows) {
      EXPECT_GE(m.q[j], low);
      EXPECT_LT(m.q[j], high);
      smallest = std::min(smallest, m.q[j]);
      largest = std::max(largest, m.q[j]);
    }
    // 2000 uniform draws leave less than 1 % of the range uncovered at either end (probability of
    // failure (0.99)^2000 ~ 2e-9 per end, and the seed is fixed).
    EXPECT_LT(smallest - low, 0.01 * (high - low)) << "joint " << j + 1;
    EXPECT_LT(high - largest, 0.01 * (high - low)) << "joint " << j + 1;
  }
  Robot unlimited = SeedNominal();
  unlimited.limits.clear();  // default +-90 deg
  for (const Measurement& m : Simulate(unlimited, truth, Random(200, 2)).rows) {
    EXPECT_LE(m.q.cwiseAbs().maxCoeff(), M_PI / 2);
  }
}

TEST(Simulator, SameSeedSameBytesOtherSeedOtherBytes) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  for (const char* protocol : {"sweep", "random"}) {
    SimulatorOptions o = Random(50, 42);
    o.protocol = protocol;
    o.noise_sigma = 10e-6;
    o.noise_range_coefficient = 5e-6;
    o.orientation = true;
    o.orientation_noise = 1e-4;
    const std::string a = DatasetToCsv(Simulate(nominal, truth, o));
    const std::string b = DatasetToCsv(Simulate(nominal, truth, o));
    EXPECT_EQ(a, b) << protocol;
    o.seed = 43;
    EXPECT_NE(DatasetToCsv(Simulate(nominal, truth, o)), a) << protocol;
  }
}

TEST(Simulator, OrientationIsTheTruthsWithoutNoise) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  SimulatorOptions o = Random(20, 9);
  o.orientation = true;
  const Dataset data = Simulate(nominal, truth, o);
  for (const Measurement& m : data.rows) {
    ASSERT_TRUE(m.orientation.has_value());
    EXPECT_NEAR(m.orientation->norm(), 1.0, 1e-15);
    const Eigen::Isometry3d T =
        truth.model().ForwardKinematics(DriveModel::ActualFromCommanded(*nominal.drives, *truth.drives, m.q));
    EXPECT_LT(RotationAngleBetween(m.orientation->toRotationMatrix(), T.linear()), 1e-6);
  }
}

// Residuals divided by the noise model's sigma at their range. With N residuals the mean square of
// standard normals has standard deviation sqrt(2 / N); the bounds below are more than six of those, and
// the seed is fixed, so the test cannot flake; a wrong noise model misses them by far.
struct NoiseStats {
  double normalized_mean_square = 0.0;  // about 1 when the model is right
  double mean = 0.0;                    // of the normalized residuals, about 0
  double rms = 0.0;                     // of the raw residuals, m
  int count = 0;
};

NoiseStats Noise(double base_distance, double a, double b, double assumed_b, uint64_t seed) {
  Robot nominal = SeedNominal(), truth = SeedTruth();
  nominal.model().SetParameter("base_x", base_distance);
  truth.model().SetParameter("base_x", base_distance);
  SimulatorOptions clean = Random(1000, seed);
  SimulatorOptions noisy = clean;
  noisy.noise_sigma = a;
  noisy.noise_range_coefficient = b;
  const Dataset exact = Simulate(nominal, truth, clean);
  const Dataset measured = Simulate(nominal, truth, noisy);
  NoiseStats s;
  double sum_sq = 0.0;
  for (size_t r = 0; r < exact.rows.size(); ++r) {
    const Eigen::Vector3d e = measured.rows[r].p - exact.rows[r].p;
    const double sigma = a + assumed_b * exact.rows[r].p.norm();
    for (int k = 0; k < 3; ++k) {
      s.normalized_mean_square += (e[k] / sigma) * (e[k] / sigma);
      s.mean += e[k] / sigma;
      sum_sq += e[k] * e[k];
      ++s.count;
    }
  }
  s.normalized_mean_square /= s.count;
  s.mean /= s.count;
  s.rms = std::sqrt(sum_sq / s.count);
  return s;
}

TEST(Simulator, TrackerNoiseGrowsWithRange) {
  const double a = 10e-6, b = 50e-6;  // 10 um + 50 um per metre
  const NoiseStats near = Noise(0.0, a, b, b, 21);
  const NoiseStats far = Noise(20.0, a, b, b, 22);
  const double bound = 6 * std::sqrt(2.0 / near.count);
  EXPECT_NEAR(near.normalized_mean_square, 1.0, bound);
  EXPECT_NEAR(far.normalized_mean_square, 1.0, bound);
  EXPECT_NEAR(near.mean, 0.0, 6 / std::sqrt(near.count));
  EXPECT_NEAR(far.mean, 0.0, 6 / std::sqrt(far.count));
  // About 1 mm RMS 20 m away, tens of micrometres near the instrument.
  EXPECT_GT(far.rms, 10 * near.rms);
  // A model that ignores the range is refuted by the same data.
  EXPECT_GT(Noise(20.0, a, b, 0.0, 22).normalized_mean_square, 50.0);
}

TEST(Simulator, InvalidOptionsAreRejected) {
  const Robot nominal = SeedNominal(), truth = SeedTruth();
  SimulatorOptions o;
  std::string why;
  o.protocol = "spiral";
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("spiral"), std::string::npos);
  EXPECT_THROW(Simulate(nominal, truth, o), std::invalid_argument);
  o = SimulatorOptions();
  o.noise_sigma = -1;
  EXPECT_FALSE(o.IsValid(&why));
  o = SimulatorOptions();
  o.start = Eigen::VectorXd::Zero(5);
  EXPECT_THROW(Simulate(nominal, truth, o), std::invalid_argument);
  const Robot three = ParseRobotYaml(
      "convention: mdh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: 0, a: 0, theta: 0, d: 0}\n"
      "  - {alpha: 90, a: 100, theta: 0, d: 0}\n  - {alpha: 0, a: 100, theta: 0, d: 0}\n",
      "three.yaml");
  Robot nominal_without_drives = nominal;
  nominal_without_drives.drives.reset();
  EXPECT_THROW(Simulate(nominal_without_drives, three, SimulatorOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
