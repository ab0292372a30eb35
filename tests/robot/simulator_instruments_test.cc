// The simulator's instruments: every simulated row satisfies its constraint on the truth arm to the noise
// (points on their axes, distances to their pivots, contacts on their planes and sockets), contacts lie
// within the joint limits and spread over the workspace, and the same seed gives the same rows.
#include <cmath>

#include <gtest/gtest.h>

#include "robot/prediction.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

SimulatorOptions With(const std::string& instrument, int poses, double noise) {
  SimulatorOptions o;
  o.protocol = "random";
  o.poses = poses;
  o.noise_sigma = noise;
  o.instrument.instrument = instrument;
  o.seed = 11;
  return o;
}

// The residual of every row in its own kind on the truth arm, whose fixtures are the simulated ones.
std::vector<Eigen::VectorXd> TruthResiduals(const Robot& nominal, Robot truth, const SimulatorOptions& o,
                                            const Dataset& data) {
  for (const Fixture& f : InstrumentFixtures(nominal, truth, o.instrument, "", o.seed)) truth.fixtures.items.push_back(f);
  const std::vector<Eigen::Vector3d> p = PredictMarkers(nominal, truth, data);
  std::vector<Eigen::VectorXd> out;
  for (size_t i = 0; i < data.rows.size(); ++i) out.push_back(RowResidual(truth, data, i, p[i]));
  return out;
}

double Rms(const std::vector<Eigen::VectorXd>& residuals) {
  double sum = 0.0;
  int count = 0;
  for (const auto& r : residuals) {
    sum += r.squaredNorm();
    count += static_cast<int>(r.size());
  }
  return std::sqrt(sum / count);
}

class Instruments : public ::testing::TestWithParam<const char*> {};

TEST_P(Instruments, EveryRowHoldsOnTheTruthArmToTheNoise) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot truth = testing::LoadExampleRobot("irb120_as_measured.yaml");
  const std::string instrument = GetParam();
  // Noise-free: exact to rounding.
  {
    const SimulatorOptions o = With(instrument, 30, 0.0);
    const Dataset data = Simulate(nominal, truth, o);
    ASSERT_EQ(data.rows.size(), 30u);
    for (const auto& r : TruthResiduals(nominal, truth, o, data)) EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-9);
  }
  // 10 um: the residuals scatter by the noise along what the instrument reads.
  const double sigma = 10e-6;
  const SimulatorOptions o = With(instrument, 90, sigma);
  const Dataset data = Simulate(nominal, truth, o);
  const std::vector<Eigen::VectorXd> residuals = TruthResiduals(nominal, truth, o, data);
  EXPECT_GT(Rms(residuals), 0.7 * sigma);
  EXPECT_LT(Rms(residuals), 1.3 * sigma);
  for (const auto& r : residuals) EXPECT_LT(r.cwiseAbs().maxCoeff(), 5 * sigma);
  // Written and read back, the rows mean the same.
  const Dataset back = ParseDatasetCsv(DatasetToCsv(data), "back.csv");
  EXPECT_LT(std::abs(Rms(TruthResiduals(nominal, truth, o, back)) - Rms(residuals)), 1e-12);
  // Every command within the limits; the same seed, the same rows.
  for (const Measurement& m : data.rows)
    for (int j = 0; j < nominal.dof(); ++j) {
      EXPECT_GE(m.q[j], nominal.Limit(j).first);
      EXPECT_LE(m.q[j], nominal.Limit(j).second);
    }
  EXPECT_EQ(DatasetToCsv(Simulate(nominal, truth, o)), DatasetToCsv(data));
}

INSTANTIATE_TEST_SUITE_P(All, Instruments, ::testing::Values("point", "partial", "distance", "plane", "socket"));

TEST(SimulatorInstruments, RowsAreSharedAmongTheFixturesInTurnAndContactsSpread) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  const Robot truth = testing::LoadExampleRobot("irb120_as_measured.yaml");
  for (const char* instrument : {"distance", "plane", "socket"}) {
    SCOPED_TRACE(instrument);
    const Dataset data = Simulate(nominal, truth, With(instrument, 12, 0.0));
    const MeasurementKind kind = data.rows[0].kind;
    EXPECT_EQ(data.FixtureNames(kind).size(), 3u);
    for (size_t i = 0; i < data.rows.size(); ++i) EXPECT_EQ(data.rows[i].fixture, data.FixtureNames(kind)[i % 3]);
    // Contacts from random starts: the joints move between rows (not one configuration repeated).
    Eigen::VectorXd spread = Eigen::VectorXd::Zero(nominal.dof());
    for (size_t i = 3; i < data.rows.size(); ++i) spread += (data.rows[i].q - data.rows[i - 3].q).cwiseAbs();
    EXPECT_GT(spread.maxCoeff() / (data.rows.size() - 3), 0.1);
  }
  // Random pivots about pivot_distance from the base origin.
  SimulatorOptions o = With("distance", 3, 0.0);
  for (const Fixture& f : InstrumentFixtures(nominal, truth, o.instrument, "", o.seed)) {
    EXPECT_NEAR((truth.model().base().inverse() * f.position).norm(), 0.7, 1e-12);
  }
}

TEST(SimulatorInstruments, TheTruthsOwnFixturesAreUsedWhenGiven) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  Robot truth = testing::LoadExampleRobot("irb120_as_measured.yaml");
  Fixture pivot;
  pivot.name = "ball";
  pivot.position = Eigen::Vector3d(1.2, 0.3, 0.1);
  truth.fixtures.items.push_back(pivot);
  const Dataset data = Simulate(nominal, truth, With("distance", 10, 0.0));
  EXPECT_EQ(data.FixtureNames(MeasurementKind::kDistance), std::vector<std::string>{"ball"});
  const std::vector<Eigen::Vector3d> p = PredictMarkers(nominal, truth, data);
  for (size_t i = 0; i < data.rows.size(); ++i) EXPECT_NEAR((p[i] - pivot.position).norm(), data.rows[i].distance, 1e-12);
}

TEST(SimulatorInstruments, PartialPointsReadOnlyTheirAxes) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  SimulatorOptions o = With("partial", 5, 0.0);
  o.instrument.axes = "xz";
  const Dataset data = Simulate(nominal, nominal, o);
  for (const Measurement& m : data.rows) EXPECT_EQ(m.axes, (std::array<bool, 3>{{true, false, true}}));
}

TEST(SimulatorInstruments, InvalidCombinationsAreRefused) {
  const Robot nominal = testing::LoadExampleRobot("irb120_mdh.yaml");
  SimulatorOptions o = With("plane", 5, 0.0);
  o.protocol = "sweep";
  EXPECT_THROW(Simulate(nominal, nominal, o), std::invalid_argument);
  o = With("distance", 5, 0.0);
  o.orientation = true;
  EXPECT_THROW(Simulate(nominal, nominal, o), std::invalid_argument);
  o = With("partial", 5, 0.0);
  o.instrument.axes = "w";
  EXPECT_THROW(Simulate(nominal, nominal, o), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
