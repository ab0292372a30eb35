// DriveModel: joint angle <-> motor counts <-> joint angle, and what a controller with the wrong ratio does
// (METHOD.md section 3).
#include <cmath>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/drive_model.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

DriveModel Drives(std::vector<double> ratio, std::vector<double> counts, std::vector<double> zero) {
  DriveModel d;
  d.ratio = Eigen::Map<Eigen::VectorXd>(ratio.data(), static_cast<Eigen::Index>(ratio.size()));
  d.counts_per_rev = Eigen::Map<Eigen::VectorXd>(counts.data(), static_cast<Eigen::Index>(counts.size()));
  d.encoder_zero = Eigen::Map<Eigen::VectorXd>(zero.data(), static_cast<Eigen::Index>(zero.size()));
  return d;
}

TEST(DriveModel, OneMotorTurnIsCountsPerRevolution) {
  // A negative ratio (a motor turning the other way, as on the Puma's joints 1 and 3) is allowed.
  const DriveModel d = Drives({100.0, -62.6111, 7946.448979591837}, {2048, 1000, 2048}, {0, 500, -12345});
  Eigen::VectorXd q(3);
  q << 2 * M_PI / 100.0, 2 * M_PI / -62.6111, 2 * M_PI / 7946.448979591837;  // one motor turn each
  const Eigen::VectorXd counts = d.CountsFromAngles(q);
  EXPECT_NEAR(counts[0], 2048, 1e-9);
  EXPECT_NEAR(counts[1], 500 + 1000, 1e-9);
  EXPECT_NEAR(counts[2], -12345 + 2048, 1e-9);
  EXPECT_EQ(d.CountsFromAngles(Eigen::VectorXd::Zero(3)), d.encoder_zero);
}

TEST(DriveModel, AnglesAndCountsAreInverses) {
  const DriveModel d = testing::SeedTruth().drives.value();
  DriveModel shifted = d;
  shifted.encoder_zero << 10, -20, 30, -40, 50, 12345678;
  Rng rng(1);
  for (int i = 0; i < 100; ++i) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) q[j] = rng.Uniform(-3, 3);
    for (const DriveModel* m : std::initializer_list<const DriveModel*>{&d, &shifted}) {
      EXPECT_LT((m->AnglesFromCounts(m->CountsFromAngles(q)) - q).cwiseAbs().maxCoeff(), 1e-14);
      const Eigen::VectorXd counts = m->CountsFromAngles(q);
      EXPECT_LT(((m->CountsFromAngles(m->AnglesFromCounts(counts)) - counts).array() / counts.array().abs().max(1.0))
                    .abs()
                    .maxCoeff(),
                1e-14);
    }
  }
}

TEST(DriveModel, CommandCountsRoundToTheNearestCount) {
  const DriveModel d = Drives({100.0, 50.0}, {2048, 2048}, {0.0, 0.25});
  Rng rng(2);
  for (int i = 0; i < 1000; ++i) {
    Eigen::VectorXd q(2);
    q << rng.Uniform(-3, 3), rng.Uniform(-3, 3);
    const std::vector<int64_t> counts = d.CommandCounts(q);
    const Eigen::VectorXd exact = d.CountsFromAngles(q);
    for (int j = 0; j < 2; ++j) EXPECT_LE(std::abs(static_cast<double>(counts[j]) - exact[j]), 0.5);
  }
  Eigen::VectorXd q(2);
  q << 2 * M_PI * 1.3 / (2048 * 100.0), 0.0;  // 1.3 counts; zero at 0.25 counts
  EXPECT_EQ(d.CommandCounts(q), (std::vector<int64_t>{1, 0}));
}

TEST(DriveModel, ControllerWithTheNominalRatioTurnsTheJointByKNominalOverKActual) {
  // The seed's Table 3: the controller converts with the nominal ratio; the joint obeys the real one.
  const DriveModel controller = testing::SeedNominal().drives.value();
  const DriveModel actual = testing::SeedTruth().drives.value();
  Eigen::VectorXd q_cmd(6);
  q_cmd << 0.5, -1.0, 1.5, -2.0, 2.5, -3.0;
  const Eigen::VectorXd q_act = DriveModel::ActualFromCommanded(controller, actual, q_cmd);
  for (int j = 0; j < 6; ++j) {
    EXPECT_DOUBLE_EQ(q_act[j], q_cmd[j] * controller.ratio[j] / actual.ratio[j]);
    // Same thing through the counts: the controller's counts read with the real ratio.
    const double counts = controller.CountsFromAngles(q_cmd)[j];
    EXPECT_NEAR(counts * 2 * M_PI / (actual.counts_per_rev[j] * actual.ratio[j]), q_act[j], 1e-15);
  }
  // Joint 5 of the seed: K 3973.22 vs 4022.85, 1.2 % short: 2.5 rad commanded -> 2.469 rad actual.
  EXPECT_NEAR(q_act[4], 2.5 * 3973.2244897959185 / 4022.85, 1e-15);
  EXPECT_LT(q_act[4], 2.47);
  // The inverse: what to command so that the joint reaches a wanted angle.
  EXPECT_LT((DriveModel::CommandedFromActual(controller, actual, q_act) - q_cmd).cwiseAbs().maxCoeff(), 1e-15);
  // A controller that knows the real ratio commands the joint exactly.
  EXPECT_EQ(DriveModel::ActualFromCommanded(actual, actual, q_cmd), q_cmd);
}

TEST(DriveModel, ValidateNamesTheProblem) {
  const auto why = [](const DriveModel& d, int dof) {
    try {
      d.Validate(dof);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(valid)");
  };
  EXPECT_EQ(why(Drives({100, 100}, {2048, 2048}, {0, 0}), 2), "(valid)");
  EXPECT_NE(why(Drives({100, 100}, {2048, 2048}, {0, 0}), 3).find("expected 3 ratios, got 2"), std::string::npos);
  EXPECT_NE(why(Drives({100, 100}, {2048}, {0, 0}), 2).find("expected 2 counts_per_rev, got 1"), std::string::npos);
  EXPECT_NE(why(Drives({100, 100}, {2048, 2048}, {0}), 2).find("encoder_zero"), std::string::npos);
  EXPECT_NE(why(Drives({100, 0}, {2048, 2048}, {0, 0}), 2).find("ratio of joint 2"), std::string::npos);
  EXPECT_NE(why(Drives({100, NAN}, {2048, 2048}, {0, 0}), 2).find("ratio of joint 2"), std::string::npos);
  EXPECT_NE(why(Drives({100, 100}, {-2048, 2048}, {0, 0}), 2).find("counts_per_rev of joint 1"), std::string::npos);
  EXPECT_NE(why(Drives({100, 100}, {2048, 2048}, {INFINITY, 0}), 2).find("encoder_zero of joint 1"), std::string::npos);
}

}  // namespace
}  // namespace kincal
