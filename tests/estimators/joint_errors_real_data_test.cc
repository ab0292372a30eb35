// Joint-level errors on the real ABB IRB 120 of ../shared/data/irb120_faro: all 982 processed
// rows in measurement order (each reached from its predecessor in the unfiltered readings), even rows fit,
// odd rows scored. Geometry alone reaches 0.523 mm held-out;
// the goals: + gravity of joints 2 and 3 <= 0.47 mm, + the approach term of every joint
// <= 0.30 mm (least_squares and ceres alike), and the three reflectors fitted jointly with that model
// <= 0.32 mm each. The geometry is Hayati's (MDH with beta where consecutive axes are parallel): axes 2
// and 3 of the IRB 120 are, and MDH cannot tilt one towards the other. Skipped when the data folder is
// absent.
#include <cstdio>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "models/conversion.h"
#include "tests/estimators/irb120_faro.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

using T = JointErrorTerm::Type;

// The nominal robot in `convention` with the IRB 120's joint speeds (ABB product specification, deg/s)
// and joint error terms: gravity of joints 2 and 3, and optionally the approach term of every joint.
Robot Irb120WithJointErrors(bool approach, std::vector<int> gravity = {1, 2},
                            const std::string& convention = "hayati") {
  Robot robot = Irb120FaroNominal();
  robot = robot.WithModel(ConvertModel(robot.model(), convention));
  robot.velocity_limits = (Eigen::VectorXd(6) << 250, 250, 250, 320, 320, 420).finished() * (M_PI / 180);
  for (int joint : gravity) {
    JointErrorTerm t;
    t.type = T::kGravity;
    t.joint = joint;
    robot.joint_errors.terms.push_back(t);
  }
  for (int joint = 0; approach && joint < 6; ++joint) {
    JointErrorTerm t;
    t.type = T::kApproach;
    t.joint = joint;
    robot.joint_errors.terms.push_back(t);
  }
  robot.joint_errors.Bind(robot.model());
  return robot;
}

struct Fit {
  double heldout_rms = NAN;
  EstimationReport report;
  Robot identified;
};

Fit FitAndScore(const std::string& method, const Robot& nominal, const Dataset& train, const Dataset& test) {
  Fit f;
  f.report = Estimators().Create(method)->Estimate(nominal, train, &f.identified);
  f.heldout_rms = EvaluatePredictions(nominal, f.identified, test).position_stats.rms;
  return f;
}

class JointErrorsRealData : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120Faro(SharedDataPath("irb120_faro"), 1, &all_),
                                    "no ../shared/data/irb120_faro");
    SplitEvenOdd(all_, &train_, &test_);
  }
  Dataset all_, train_, test_;
};

TEST_P(JointErrorsRealData, GravityOfJoints2And3) {
  const Fit f = FitAndScore(GetParam(), Irb120WithJointErrors(false), train_, test_);
  std::printf("%s, geometry + gravity 2, 3: held-out RMS %.4f mm (goal <= 0.47; geometry alone 0.523)\n",
              GetParam().c_str(), f.heldout_rms * 1e3);
  EXPECT_NE(f.report.status, EstimationStatus::kFailed) << f.report.BriefReport();
  EXPECT_LE(f.heldout_rms, 0.47e-3);
}

TEST_P(JointErrorsRealData, GravityAndTheApproachOfEveryJoint) {
  const Fit f = FitAndScore(GetParam(), Irb120WithJointErrors(true), train_, test_);
  std::printf("%s, geometry + gravity 2, 3 + approach 1-6: held-out RMS %.4f mm (goal <= 0.30)\n", GetParam().c_str(),
              f.heldout_rms * 1e3);
  for (const auto& p : f.report.parameters) {
    if (p.name.rfind("approach", 0) == 0) {
      std::printf("  %s = %.3g s (%.2f mdeg per rad/s) +- %.2g\n", p.name.c_str(), p.value, p.value * 180 / M_PI * 1e3,
                  p.stddev);
    }
  }
  EXPECT_NE(f.report.status, EstimationStatus::kFailed) << f.report.BriefReport();
  EXPECT_LE(f.heldout_rms, 0.30e-3);
}

INSTANTIATE_TEST_SUITE_P(Estimators, JointErrorsRealData, ::testing::Values("least_squares", "ceres"));

// The three reflectors as markers SMR1..3 of one dataset (three rows per pose, in measurement order; the
// split by pose): one base, one offset per reflector.
Dataset ThreeReflectors() {
  Dataset all;
  if (!LoadIrb120FaroReflectors(SharedDataPath("irb120_faro"), {1, 2, 3}, &all)) return Dataset();
  for (size_t r = 0; r < all.rows.size(); ++r) all.rows[r].split = (r / 3) % 2 == 0 ? Split::kTrain : Split::kTest;
  return all;
}

// Held-out RMS of each reflector, fitted jointly by least_squares.
std::vector<double> ThreeReflectorHeldOut(const Dataset& all, Robot nominal, const std::string& label) {
  for (int smr = 1; smr <= 3; ++smr) nominal.markers["SMR" + std::to_string(smr)] = Eigen::Vector3d::Zero();
  const Dataset train = all.Subset(Split::kTrain), test = all.Subset(Split::kTest);
  Robot identified;
  YAML::Node options;
  options["max_iterations"] = 200;  // from markers at the flange, 150 mm off
  const EstimationReport report = Estimators().Create("least_squares", options)->Estimate(nominal, train, &identified);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  std::vector<double> out;
  for (int smr = 1; smr <= 3; ++smr) {
    Dataset one = test;
    one.rows.clear();
    for (const auto& m : test.rows)
      if (m.marker == "SMR" + std::to_string(smr)) one.rows.push_back(m);
    out.push_back(EvaluatePredictions(nominal, identified, one).position_stats.rms);
    std::printf("three reflectors jointly, %s, SMR%d: held-out RMS %.4f mm (goal <= 0.32)\n", label.c_str(), smr,
                out.back() * 1e3);
  }
  return out;
}

// With the model of reflector 1 (geometry, gravity 2, 3, approach 1-6), every reflector within the target
// 0.32 mm. SMR2 sits 216 mm beyond the flange and 116 mm off its axis: it sees the tool's orientation error
// most. In MDH, which cannot tilt axis 3 towards axis 2, it stays at 0.327 mm; Hayati's beta_3 (0.68 mrad
// here) brings it to 0.315. The wrist's gravity terms (joints 4 and 5, the "gravity terms of the
// wrist and payload") reduce the orientation error further.
TEST(JointErrorsRealData3, ThreeReflectorsFittedJointly) {
  const Dataset all = ThreeReflectors();
  KINCAL_SKIP_WITHOUT_SHARED_DATA(!all.rows.empty(), "no ../shared/data/irb120_faro");
  const auto same = ThreeReflectorHeldOut(all, Irb120WithJointErrors(true), "gravity 2, 3 + approach 1-6");
  for (double rms : same) EXPECT_LE(rms, 0.32e-3);
  const auto mdh = ThreeReflectorHeldOut(all, Irb120WithJointErrors(true, {1, 2}, "mdh"), "the same in MDH");
  EXPECT_GT(mdh[1], same[1] + 0.005e-3);
  const auto wrist = ThreeReflectorHeldOut(all, Irb120WithJointErrors(true, {1, 2, 3, 4}), "+ gravity 4, 5");
  for (double rms : wrist) EXPECT_LE(rms, 0.30e-3);
}

// The measurement sequence matters: 16 of the 982 processed poses followed a pose the data's author
// removed, and were reached from it. Their previous pose from the unfiltered readings (measured_joints.txt)
// instead of the processed row before them brings reflector 1 from 0.275 to 0.265 mm.
TEST(JointErrorsRealData, ThePreviousPosesOfTheUnfilteredSequence) {
  Dataset all;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120Faro(SharedDataPath("irb120_faro"), 1, &all),
                                  "no ../shared/data/irb120_faro");
  int from_sequence = 0;
  for (const auto& m : all.rows) from_sequence += m.from_q.has_value();
  EXPECT_EQ(from_sequence, 16);
  Dataset processed_order = all;
  for (auto& m : processed_order.rows) m.from_q.reset();
  double rms[2];
  for (int k = 0; k < 2; ++k) {
    Dataset train, test;
    SplitEvenOdd(k == 0 ? all : processed_order, &train, &test);
    rms[k] = FitAndScore("least_squares", Irb120WithJointErrors(true), train, test).heldout_rms;
  }
  std::printf(
      "gravity 2, 3 + approach 1-6, reflector 1: previous poses from the sequence %.4f mm, from the "
      "processed rows %.4f mm\n",
      rms[0] * 1e3, rms[1] * 1e3);
  EXPECT_LT(rms[0], rms[1] - 0.005e-3);
}

}  // namespace
}  // namespace kincal::testing
