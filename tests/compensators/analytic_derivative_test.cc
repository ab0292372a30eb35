// The seed's 12-equation method (METHOD.md 4) and the 6-D Jacobian method: options, the paper's plain
// form, independence of the solution from the weighting, quadratic convergence.
#include <gtest/gtest.h>

#include <algorithm>

#include "compensators/analytic_derivative/analytic_derivative_compensator.h"
#include "compensators/jacobian/jacobian_compensator.h"
#include "tests/compensators/compensator_fixture.h"

namespace kincal {
namespace {

using testing::Arm;

CompensationResult PrepareAndRun(Compensator& c, const CompensationTarget& target) {
  c.Prepare(Arm().nominal, Arm().identified);
  return c.Compensate(target);
}

TEST(AnalyticDerivativeOptions, FromYaml) {
  const auto o = AnalyticDerivativeCompensator::Options::FromYaml(
      YAML::Load("{length_scale: 500mm, plain: false, max_iterations: 7, position_tolerance: 1um, "
                 "orientation_tolerance: 1e-9, singular_ratio: 0.01, trust_radius: 0.2, max_step_halvings: 3}"));
  EXPECT_DOUBLE_EQ(o.length_scale, 0.5);
  EXPECT_EQ(o.iteration.max_iterations, 7);
  EXPECT_DOUBLE_EQ(o.iteration.position_tolerance, 1e-6);
  EXPECT_DOUBLE_EQ(o.iteration.orientation_tolerance, 1e-9);
  EXPECT_DOUBLE_EQ(o.iteration.singular_ratio, 0.01);
  EXPECT_DOUBLE_EQ(o.iteration.trust_radius, 0.2);
  EXPECT_EQ(o.iteration.max_step_halvings, 3);
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  EXPECT_THROW(AnalyticDerivativeCompensator::Options::FromYaml(YAML::Load("{lenght_scale: 1}")),
               std::invalid_argument);
  AnalyticDerivativeCompensator::Options bad;
  bad.length_scale = 0;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_THROW(Compensators().Create("analytic_derivative", YAML::Load("{length_scale: -1}")), std::invalid_argument);
}

TEST(JacobianOptions, FromYaml) {
  const auto o = JacobianCompensator::Options::FromYaml(YAML::Load("{length_scale: 0.25, max_iterations: 5}"));
  EXPECT_DOUBLE_EQ(o.length_scale, 0.25);
  EXPECT_EQ(o.iteration.max_iterations, 5);
  EXPECT_THROW(JacobianCompensator::Options::FromYaml(YAML::Load("{plain: true}")), std::invalid_argument);
}

// The paper's form verbatim (SI metres, A^+ B, every step taken) reaches the same joints as the default.
TEST(AnalyticDerivative, PlainFormReachesTheSameSolution) {
  AnalyticDerivativeCompensator::Options plain_options;
  plain_options.plain = true;
  AnalyticDerivativeCompensator plain(plain_options), weighted;
  EXPECT_DOUBLE_EQ(plain.options().length_scale, 1.0);
  EXPECT_EQ(plain.options().iteration.singular_ratio, 0.0);
  for (const CompensationTarget& target : testing::WellConditionedTargets(20, 21).targets) {
    const CompensationResult a = PrepareAndRun(plain, target), b = PrepareAndRun(weighted, target);
    EXPECT_EQ(a.report.status, CompensationStatus::kConverged);
    EXPECT_LE(a.report.position_error, 1e-12);
    EXPECT_LE(a.report.orientation_error, 1e-12);
    EXPECT_LE((a.q_actual - b.q_actual).cwiseAbs().maxCoeff(), 1e-11);
  }
}

// For a reachable 6-D target the solution does not depend on how position weighs against orientation;
// the weight only changes the path (and the result for targets that cannot be met exactly).
TEST(AnalyticDerivative, WeightChangesThePathNotTheSolution) {
  for (const CompensationTarget& target : testing::WellConditionedTargets(10, 22).targets) {
    Eigen::VectorXd reference;
    for (const double length_scale : {0.001, 0.5, 1.0, 10.0}) {
      AnalyticDerivativeCompensator::Options o;
      o.length_scale = length_scale;
      AnalyticDerivativeCompensator c(o);
      const CompensationResult r = PrepareAndRun(c, target);
      ASSERT_EQ(r.report.status, CompensationStatus::kConverged) << length_scale;
      if (reference.size() == 0) reference = r.q_actual;
      EXPECT_LE((r.q_actual - reference).cwiseAbs().maxCoeff(), 1e-11) << length_scale;
    }
  }
}

// Newton-type convergence: the pose error contracts quadratically, e_(k+1) <= C e_k^2 above the floor.
TEST(IterativeCompensators, ConvergeQuadratically) {
  AnalyticDerivativeCompensator analytic;
  JacobianCompensator jacobian;
  for (Compensator* c : std::initializer_list<Compensator*>{&analytic, &jacobian}) {
    double worst = 0.0;
    for (const CompensationTarget& target : testing::WellConditionedTargets(40, 23).targets) {
      const CompensationResult r = PrepareAndRun(*c, target);
      const auto& p = r.report.position_history;
      const auto& o = r.report.orientation_history;
      for (size_t k = 0; k + 1 < p.size(); ++k) {
        const double e = p[k] + 0.5 * o[k], next = p[k + 1] + 0.5 * o[k + 1];  // m
        if (e > 1e-7) worst = std::max(worst, next / (e * e));
      }
    }
    EXPECT_LT(worst, 1e4) << c->name();  // 1/m: 1 mm -> 10 um at worst
    RecordProperty(c->name() + "_contraction", std::to_string(worst));
  }
}

// The seed's claim is 4 iterations; from the controller's seeds, nearly every well-conditioned target
// meets 1e-9 mm and 1e-12 rad within 4 (bench/compensators_bench.cc measures the exact share).
TEST(AnalyticDerivative, IterationCounts) {
  AnalyticDerivativeCompensator c;
  std::vector<int> iterations;
  for (const CompensationTarget& target : testing::WellConditionedTargets(100, 24).targets) {
    iterations.push_back(PrepareAndRun(c, target).report.iterations);
  }
  std::sort(iterations.begin(), iterations.end());
  const int within4 = static_cast<int>(std::upper_bound(iterations.begin(), iterations.end(), 4) - iterations.begin());
  EXPECT_GE(within4, 85);
  EXPECT_LE(iterations[50], 4);
  RecordProperty("within_4_iterations_of_100", within4);
}

}  // namespace
}  // namespace kincal
