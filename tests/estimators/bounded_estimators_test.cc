// nlopt and ipopt specifics: options, bounds that bind (both solve the same bounded problem and agree),
// limits reported as such; and the four error-model estimators report identically. The selectable
// algorithms are in selectable_algorithms_test.cc.
#include <cmath>
#include <map>

#include "estimators/ipopt/ipopt_estimator.h"
#include "estimators/nlopt/nlopt_estimator.h"
#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

bool IsJointParameter(const std::string& name) {
  for (const char* prefix : {"alpha_", "a_", "theta_", "d_"}) {
    if (name.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

TEST(NloptOptions, ReadFromYamlAndRejectBadValues) {
  const NloptOptions o = NloptOptions::FromYaml(YAML::Load(R"(
algorithm: LN_BOBYQA
max_evaluations: 300
function_tolerance: 1e-10
bound_length: 2mm
bound_ratio: 0.01
)"));
  EXPECT_EQ(o.algorithm, "LN_BOBYQA");
  EXPECT_EQ(o.max_evaluations, 300);
  EXPECT_DOUBLE_EQ(o.function_tolerance, 1e-10);
  EXPECT_DOUBLE_EQ(o.error_model.bounds.length, 2e-3);
  EXPECT_DOUBLE_EQ(o.error_model.bounds.ratio, 0.01);
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  EXPECT_EQ(NloptOptions().algorithm, "LD_SLSQP");
  EXPECT_THROW(NloptOptions::FromYaml(YAML::Load("{algoritm: LD_SLSQP}")), std::invalid_argument);
  // Global algorithms and unknown names are refused, naming the accepted ones.
  NloptOptions bad;
  bad.algorithm = "GN_DIRECT";
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("LN_BOBYQA"), std::string::npos);
  EXPECT_THROW(Estimators().Create("nlopt", YAML::Load("{algorithm: LD_NEWTON}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("nlopt", YAML::Load("{max_evaluations: 0}")), std::invalid_argument);
}

TEST(IpoptOptions, ReadFromYamlAndRejectBadValues) {
  const IpoptOptions o = IpoptOptions::FromYaml(YAML::Load(R"(
hessian: limited_memory
max_iterations: 40
tolerance: 1e-9
print_level: 5
bound_angle_deg: 1
)"));
  EXPECT_EQ(o.hessian, "limited_memory");
  EXPECT_EQ(o.max_iterations, 40);
  EXPECT_DOUBLE_EQ(o.tolerance, 1e-9);
  EXPECT_EQ(o.print_level, 5);
  EXPECT_DOUBLE_EQ(o.error_model.bounds.angle, M_PI / 180.0);
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  EXPECT_EQ(IpoptOptions().hessian, "gauss_newton");
  EXPECT_EQ(IpoptOptions().print_level, 0);
  EXPECT_THROW(IpoptOptions::FromYaml(YAML::Load("{hessain: exact}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("ipopt", YAML::Load("{hessian: exact}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("ipopt", YAML::Load("{print_level: 13}")), std::invalid_argument);
  EXPECT_THROW(Estimators().Create("ipopt", YAML::Load("{tolerance: 0}")), std::invalid_argument);
}

class BoundedEstimatorTest : public ::testing::TestWithParam<std::string> {};

// Bounds tighter than the truth's distance from the nominal: Table 2 moves a_5 by 3.9 mm, theta_4 by
// 1.07 deg and ratio 5 by 1.25 %. Every parameter stays inside, some end on their bound, the report says
// so, and NLopt and Ipopt, solving the same bounded problem, find the same point.
TEST_P(BoundedEstimatorTest, BindingBoundsAreRespectedAndBothSolversAgree) {
  const SimulatedCase c = RandomPoseCase(80, 10e-6, 31);
  const YAML::Node options = YAML::Load("{bound_length: 1mm, bound_angle_deg: 0.5, bound_ratio: 0.01}");
  EstimationReport report;
  RunEstimator(GetParam(), c.nominal, c.data, &report, options);
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  int on_bound = 0;
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    double distance = 0.0, bound = 0.0;
    if (p.name.rfind("ratio_", 0) == 0) {
      distance = std::abs(p.value / p.nominal - 1.0);
      bound = 0.01;
    } else if (IsJointParameter(p.name)) {
      distance = std::abs(p.value - p.nominal);
      bound = p.unit == "m" ? 1e-3 : 0.5 * M_PI / 180.0;
    } else {
      continue;  // base and tool: bounds far wider than their errors
    }
    EXPECT_LE(distance, bound * (1.0 + 1e-9)) << p.name;
    on_bound += distance >= bound * (1.0 - 2e-6);  // within 1e-6 of the bound's width (2 bound)
  }
  EXPECT_GE(on_bound, 3);
  EXPECT_EQ(report.details["parameters_at_bounds"].get<int>(), on_bound);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.back().find("bound"), std::string::npos);

  const std::string other = GetParam() == "nlopt" ? "ipopt" : "nlopt";
  EstimationReport other_report;
  RunEstimator(other, c.nominal, c.data, &other_report, options);
  const auto expected = ByName(other_report);
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    EXPECT_LT(std::abs(p.value - expected.at(p.name)->value), 1e-3 * p.stddev) << p.name;
  }
}

TEST_P(BoundedEstimatorTest, LimitsAreReportedAsLimits) {
  const SimulatedCase c = RandomPoseCase(60, 10e-6, 32);
  const YAML::Node options = YAML::Load(GetParam() == "nlopt" ? "{max_evaluations: 5}" : "{max_iterations: 2}");
  EstimationReport report;
  RunEstimator(GetParam(), c.nominal, c.data, &report, options);
  EXPECT_EQ(report.status, EstimationStatus::kIterationLimit) << report.BriefReport();
  EXPECT_GT(report.final_rms, 0.0);
  EXPECT_EQ(report.parameters.size(), 42u);  // complete all the same: 24 joint, 6 base, 6 tool, 6 ratios
}

INSTANTIATE_TEST_SUITE_P(Bounded, BoundedEstimatorTest, ::testing::Values("nlopt", "ipopt"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// Same preparation, same covariance helpers: apart from how they minimise, the four reports coincide.
TEST(ErrorModelEstimators, AllFourReportIdentically) {
  const SimulatedCase c = RandomPoseCase(80, 20e-6, 34);
  std::vector<EstimationReport> reports;
  for (const auto& name : kErrorModelEstimators) {
    reports.emplace_back();
    RunEstimator(name, c.nominal, c.data, &reports.back(), FixtureOptions(name));
  }
  const EstimationReport& first = reports.front();
  for (size_t k = 1; k < reports.size(); ++k) {
    const EstimationReport& r = reports[k];
    SCOPED_TRACE(kErrorModelEstimators[k]);
    EXPECT_EQ(r.status, EstimationStatus::kConverged) << r.BriefReport();
    EXPECT_EQ(r.fixed_parameters, first.fixed_parameters);
    EXPECT_EQ(r.condition_number, first.condition_number);
    EXPECT_NEAR(r.final_rms, first.final_rms, 1e-9 * first.final_rms);
    EXPECT_NEAR(r.details["sigma_m"].get<double>(), first.details["sigma_m"].get<double>(),
                1e-9 * first.details["sigma_m"].get<double>());
    EXPECT_EQ(r.details["observability"], first.details["observability"]);
    ASSERT_EQ(r.parameters.size(), first.parameters.size());
    for (size_t i = 0; i < r.parameters.size(); ++i) {
      EXPECT_EQ(r.parameters[i].name, first.parameters[i].name);
      EXPECT_EQ(r.parameters[i].free, first.parameters[i].free);
      EXPECT_EQ(r.parameters[i].note, first.parameters[i].note);
    }
    EXPECT_GT(r.wall_time_seconds, 0.0);
    EXPECT_GT(r.iterations, 0);
  }
}

}  // namespace
}  // namespace kincal::testing
