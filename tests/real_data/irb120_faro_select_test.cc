// docs/guide/real_data.md's "--select" row of irb120_faro: reflector 1, even poses fit, odd poses scored, selection
// from examples/robots/irb120_joint_errors.yaml (skips without ../shared/data/irb120_faro, fails under
// KINCAL_REQUIRE_DATA=1). Richer is right on this arm: selection keeps the approach terms.
#include <cstdio>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "robot/prediction.h"
#include "tests/estimators/irb120_faro.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

TEST(Irb120FaroSelect, Reflector1FromTheRichestFile) {
  Dataset train, test;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(LoadIrb120FaroSplit(SharedDataPath("irb120_faro"), 1, &train, &test),
                                  "no ../shared/data/irb120_faro");
  Robot rich = LoadExampleRobot("irb120_joint_errors.yaml");
  rich.markers.clear();  // reflector 1 is the tool origin
  Robot identified;
  const EstimationReport report = Estimators()
                                      .Create("least_squares", YAML::Load("{max_iterations: 200, select: true}"))
                                      ->Estimate(rich, train, &identified);
  const std::string chosen = ChosenCandidate(report.details.at("selection"));
  const double rms = EvaluatePredictions(rich, identified, test).position_stats.rms;
  std::printf("irb120_faro reflector 1, selected %s: held-out RMS %.4f mm\n", chosen.c_str(), rms * 1e3);
  EXPECT_EQ(chosen, "+ approach 5");
  EXPECT_NEAR(rms * 1e3, 0.247, 0.001);
}

}  // namespace
}  // namespace kincal::testing
