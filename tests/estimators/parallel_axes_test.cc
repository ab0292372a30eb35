// Parallel consecutive axes (METHOD.md section 2): the IRB 120's axes 2 and 3. A tilt of axis 3 towards
// axis 2 is Hayati's beta_3; MDH has no parameter for it (the common normal's foot would run away). The
// error-model estimators identify a Hayati model with beta only where it means something: held, with
// the reason, on the rows whose axes are not parallel, where it duplicates d and theta of the row before.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "models/conversion.h"
#include "models/hayati_model.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

Robot Irb120(const std::string& convention) {
  const Robot mdh = LoadExampleRobot("irb120_mdh.yaml");
  return mdh.WithModel(ConvertModel(mdh.model(), convention));
}

// A truth whose axis 3 leans 0.5 mrad towards axis 2, with other small errors, seen from a tracker.
Robot TiltedTruth() {
  Robot truth = Irb120("hayati");
  KinematicModel& m = truth.model();
  m.SetParameter("beta_3", 0.5e-3);
  m.SetParameter("a_3", m.Parameter("a_3") + 0.2e-3);
  m.SetParameter("alpha_4", m.Parameter("alpha_4") + 0.3e-3);
  m.SetParameter("theta_2", m.Parameter("theta_2") + 0.4e-3);
  m.SetParameter("d_4", m.Parameter("d_4") - 0.15e-3);
  m.SetBase(PoseFromXyzRpy(Eigen::Vector3d(2.1, 0.4, -0.5), Eigen::Vector3d(0.01, -0.02, 0.7)));
  m.SetTool(PoseFromXyzRpy(Eigen::Vector3d(0.02, -0.01, 0.12), Eigen::Vector3d::Zero()));
  return truth;
}

TEST(ParallelAxes, BetaIsRedundantExactlyWhereTheAxesAreNotParallel) {
  const Robot robot = Irb120("hayati");
  // Rows: axis 1 along the base's z (parallel), 1-2 and 3-4, 4-5, 5-6 at right angles, 2-3 parallel.
  const bool expected[6] = {false, true, false, true, true, true};
  for (int joint = 1; joint <= 6; ++joint) {
    EXPECT_EQ(HayatiBetaIsRedundant(robot.model(), joint), expected[joint - 1]) << joint;
  }
  Robot leaning = robot;
  leaning.model().SetParameter("alpha_3", 0.2);  // 11.5 deg: no longer parallel
  EXPECT_TRUE(HayatiBetaIsRedundant(leaning.model(), 3));
  EXPECT_THROW(HayatiBetaIsRedundant(Irb120("mdh").model(), 3), std::invalid_argument);
}

TEST(ParallelAxes, HayatiRecoversATiltThatMdhCannotRepresent) {
  const Robot nominal_hayati = Irb120("hayati"), truth = TiltedTruth();
  const Dataset train = RandomPoses(nominal_hayati, truth, 60, 11), test = RandomPoses(nominal_hayati, truth, 200, 12);
  YAML::Node options;
  options["parameter_tolerance"] = 1e-12;
  Robot identified;
  const EstimationReport report =
      Estimators().Create("least_squares", options)->Estimate(nominal_hayati, train, &identified);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  EXPECT_LT(EvaluatePredictions(nominal_hayati, identified, test).position_stats.max, 1e-10);
  EXPECT_NEAR(identified.model().Parameter("beta_3"), 0.5e-3, 1e-11);
  for (const ParameterEstimate& p : report.parameters) {
    if (p.name == "beta_2" || p.name == "beta_4" || p.name == "beta_5" || p.name == "beta_6") {
      EXPECT_FALSE(p.free) << p.name;
      EXPECT_NE(p.note.find("are not parallel"), std::string::npos) << p.name << ": " << p.note;
    }
    if (p.name == "beta_3") {
      EXPECT_TRUE(p.free);
    }
    if (p.free) {  // a regular problem: with beta free on the non-parallel rows too, it was near-singular
      EXPECT_TRUE(std::isfinite(p.stddev)) << p.name;
    }
  }

  // The same data in MDH: the tilt has no parameter, a few micrometres are left wherever the arm reaches.
  const Robot nominal_mdh = Irb120("mdh");
  Robot mdh_identified;
  Estimators().Create("least_squares", options)->Estimate(nominal_mdh, train, &mdh_identified);
  const double mdh_rms = EvaluatePredictions(nominal_mdh, mdh_identified, test).position_stats.rms;
  std::printf("held-out RMS of the MDH fit of a 0.5 mrad tilt between parallel axes: %.2f um\n", mdh_rms * 1e6);
  EXPECT_GT(mdh_rms, 10e-6);
}

}  // namespace
}  // namespace kincal::testing
