// least_squares on real measurements: the ABB IRB 120 laser-tracker set (../shared/data/irb120_faro,
// skipped when absent). Fitted on the even rows, scored on the odd rows, reflector 1, position residuals.
// Reference (data README): 0.629 mm held-out RMS with base, reflector and joint offsets, 0.525 mm with all
// geometry, lightly damped.
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "tests/estimators/irb120_faro.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

TEST(LeastSquaresRealData, Irb120FaroHeldOutErrorMatchesTheReferenceFit) {
  Dataset train, test;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120FaroSplit(SharedDataPath("irb120_faro"), 1, &train, &test),
                                  "no irb120_faro data");
  const Robot nominal = Irb120FaroNominal();
  Robot identified;
  const EstimationReport report = Estimators().Create("least_squares")->Estimate(nominal, train, &identified);
  const ErrorStats train_stats = EvaluatePredictions(nominal, identified, train).position_stats;
  const ErrorStats heldout = EvaluatePredictions(nominal, identified, test).position_stats;
  std::printf("%s\n", report.BriefReport().c_str());
  std::string fixed;
  for (const auto& f : report.fixed_parameters) fixed += " " + f;
  std::printf("held (not identifiable):%s\ncondition number %.4g, O1 %.3g m, O3 %.3g m\n", fixed.c_str(),
              report.condition_number, report.details["observability"]["O1"].get<double>(),
              report.details["observability"]["O3"].get<double>());
  std::printf("train (%d rows): RMS %.4f mm, mean %.4f mm, max %.4f mm\n", train_stats.count, train_stats.rms * 1e3,
              train_stats.mean * 1e3, train_stats.max * 1e3);
  std::printf("held-out (%d rows): RMS %.4f mm, mean %.4f mm, max %.4f mm (reference 0.525 mm RMS)\n", heldout.count,
              heldout.rms * 1e3, heldout.mean * 1e3, heldout.max * 1e3);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  // Joints 2 and 3 are parallel: d_2 and d_3 move the arm alike, so one of them is held.
  const auto& held = report.fixed_parameters;
  EXPECT_NE(std::find(held.begin(), held.end(), "d_3"), held.end());
  EXPECT_LE(heldout.rms, 0.530e-3);
}

}  // namespace
}  // namespace kincal::testing
