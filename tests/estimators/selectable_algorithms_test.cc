// The selectable algorithms of the bounded estimators: NLopt's derivative-free BOBYQA and Ipopt's
// limited-memory BFGS reach the same minimum as least_squares. About 2 s in Release; labelled slow because
// BOBYQA's 8000 passes and Ipopt's quasi-Newton bookkeeping (allocation-heavy inside the unsanitized
// Ipopt) take 20-40 s under AddressSanitizer.
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

// The derivative-free BOBYQA and the limited-memory Hessian against least_squares on 50 noisy poses.
class SelectableAlgorithmTest : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(SelectableAlgorithmTest, ReachesTheLeastSquaresMinimum) {
  const auto& [name, yaml] = GetParam();
  const SimulatedCase c = RandomPoseCase(50, 20e-6, 33);
  EstimationReport reference, report;
  RunEstimator("least_squares", c.nominal, c.data, &reference, FixtureOptions("least_squares"));
  RunEstimator(name, c.nominal, c.data, &report, YAML::Load(yaml));
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  const auto expected = ByName(reference);
  double worst = 0.0;
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    const ParameterEstimate& e = *expected.at(p.name);
    worst = std::max(worst, std::abs(p.value - e.value) / e.stddev);
  }
  EXPECT_LT(worst, 1e-3);
  std::printf("%s %s: %s\n  largest difference to least_squares %.3g standard deviations\n", name.c_str(), yaml.c_str(),
              report.BriefReport().c_str(), worst);
}

INSTANTIATE_TEST_SUITE_P(Selectable, SelectableAlgorithmTest,
                         ::testing::Values(std::make_pair(std::string("nlopt"), std::string("{algorithm: LN_BOBYQA}")),
                                           std::make_pair(std::string("ipopt"),
                                                          std::string("{hessian: limited_memory}"))),
                         [](const auto& info) { return info.param.first; });

}  // namespace
}  // namespace kincal::testing
