// Priors (maximum a posteriori) and weakly identifiable parameters of the error-model estimators
// (estimators/error_model/error_model_problem.h PriorOptions, weak_parameters.h).
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "tests/estimators/error_model_fixture.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

// The UR10 of examples/robots/ur10_dh.yaml with a 100 mm tool (the start and the controller).
Robot UrNominal() {
  Robot r = LoadExampleRobot("ur10_dh.yaml");
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Eigen::Vector3d(0.0, 0.0, 0.1);
  r.model().SetTool(tool);
  return r;
}

// The truth: every joint parameter off by up to 0.5 mm or 1 mrad (seeded), the tool by 1 mm, seen from
// the tracker frame of the fixture.
Robot UrTruth(const Robot& nominal, uint64_t seed) {
  Robot t = nominal;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& info : t.model().parameter_info()) {
    if (info.group != ParameterInfo::Group::kJoint) continue;
    const double delta = info.kind == ParameterInfo::Kind::kLength ? 0.5e-3 : 1e-3;
    t.model().SetParameter(info.name, t.model().Parameter(info.name) + delta * u(rng));
  }
  Eigen::Isometry3d tool = t.model().tool();
  tool.translation() += Eigen::Vector3d(0.3e-3, -0.5e-3, 1e-3);
  t.model().SetTool(tool);
  t.model().SetBase(TrackerBase());
  return t;
}

// A 1000-pose grid, 10 x 10 x 10 over joints 1-3, the wrist turning little: joint 4 through 40 deg, joint 5
// through 11 deg and joint 6 through 290 deg, as an arm taught on a regular grid of tool positions with the tool kept
// pointing down. Positions of the tool origin, noise `noise` per axis (seeded).
Dataset UrGrid(const Robot& truth, double noise, uint64_t seed) {
  Dataset d;
  d.dof = 6;
  d.source = "ur_grid";
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  int k = 0;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      for (int l = 0; l < 10; ++l, ++k) {
        Measurement m;
        m.q.resize(6);
        m.q << -0.8 + 0.16 * i, -2.2 + 0.12 * j, 0.6 + 0.15 * l, -1.6 + 0.7 * std::sin(0.37 * k),
            -1.5708 + 0.1 * std::cos(0.23 * k), 2.5 * std::sin(0.71 * k);
        m.p = PredictToolPose(truth, m.q).translation() + Eigen::Vector3d(n(rng), n(rng), n(rng));
        d.rows.push_back(m);
      }
    }
  }
  return d;
}

TEST(WeakParameters, UrGridGeometryOnlyConvergesAndNamesTheWristAsWeak) {
  const Robot nominal = UrNominal();
  const Robot truth = UrTruth(nominal, 7);
  const Dataset data = UrGrid(truth, 100e-6, 11);
  YAML::Node options(YAML::NodeType::Map);
  options["max_iterations"] = 50;
  EstimationReport report;
  RunEstimator("least_squares", nominal, data, &report, options);
  std::cout << report.BriefReport() << "\n";
  for (const auto& w : report.warnings) std::cout << "warning: " << w << "\n";
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.message;
  for (const std::string name : {"alpha_5", "a_5", "d_5"}) {
    bool weak = false;
    for (const auto& p : report.parameters) weak = weak || (p.name == name && p.weak);
    EXPECT_TRUE(weak) << name << " is not reported weak";
  }
}

// The IRB 120 with a 100 mm tool on the axis of joint 6, seen from the tracker frame of the fixture, every
// joint parameter off by up to 0.5 mm or 1 mrad (seeded), 300 random poses within the joint limits with
// 50 um of noise per axis: positions of a point on axis 6 leave the wrist's rows in a flat valley.
struct ToolOnAxisCase {
  Robot nominal, truth;
  Dataset data;
};
ToolOnAxisCase Irb120ToolOnAxis6() {
  ToolOnAxisCase c;
  c.nominal = LoadExampleRobot("irb120_mdh.yaml");
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Eigen::Vector3d(0.0, 0.0, 0.1);
  c.nominal.model().SetTool(tool);
  c.truth = c.nominal;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& info : c.truth.model().parameter_info()) {
    if (info.group != ParameterInfo::Group::kJoint) continue;
    const double delta = info.kind == ParameterInfo::Kind::kLength ? 0.5e-3 : 1e-3;
    c.truth.model().SetParameter(info.name, c.truth.model().Parameter(info.name) + delta * u(rng));
  }
  c.truth.model().SetBase(TrackerBase());
  c.data.dof = 6;
  c.data.source = "irb120_tool_on_axis_6";
  std::normal_distribution<double> n(0.0, 50e-6);
  const auto& limits = c.nominal.limits;
  for (int k = 0; k < 300; ++k) {
    Measurement m;
    m.q.resize(6);
    for (int j = 0; j < 6; ++j) {
      m.q[j] = limits[j].first + 0.5 * (1.0 + u(rng)) * (limits[j].second - limits[j].first);
    }
    m.p = PredictToolPose(c.truth, m.q).translation() + Eigen::Vector3d(n(rng), n(rng), n(rng));
    c.data.rows.push_back(m);
  }
  return c;
}

// What "determined" is judged against without a prior: the default prior sd of the parameter's kind
// (error_model_problem.h PriorOptions); 0 for the base and the tool, which have none.
double ReferenceSd(const ParameterEstimate& p) {
  if (p.name.rfind("base_", 0) == 0 || p.name.rfind("tool_", 0) == 0) return 0.0;
  if (p.name.rfind("theta_", 0) == 0) return 20e-3;
  return p.unit == "m" ? 1e-3 : 2e-3;
}

// The issue: "no free parameter whose posterior sd exceeds its prior sd goes unreported". A fit that runs
// out of iterations in a flat valley (the wrist's rows here, sd of tenths of a radian from the data) is
// analysed as a converged one: its weak parameters are named, those without a prior held with the reason,
// and it refits the rest with a budget of its own.
TEST(WeakParameters, AFlatValleyAtTheIterationLimitNamesItsWeakParameters) {
  const ToolOnAxisCase c = Irb120ToolOnAxis6();
  YAML::Node options(YAML::NodeType::Map);
  options["max_iterations"] = 50;
  EstimationReport report;
  RunEstimator("least_squares", c.nominal, c.data, &report, options);
  std::cout << report.BriefReport() << "\n";
  for (const auto& w : report.warnings) std::cout << "warning: " << w << "\n";
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.message;
  int held_weak = 0;
  for (const auto& p : report.parameters) {
    if (p.free) {
      EXPECT_TRUE(p.weak || !(p.stddev > ReferenceSd(p)) || ReferenceSd(p) == 0.0)
          << p.name << ": sd " << p.stddev << " above " << ReferenceSd(p) << " and not reported weak";
    } else if (p.note.find("weakly identifiable") != std::string::npos) {
      EXPECT_TRUE(p.weak) << p.name;
      ++held_weak;
    }
  }
  EXPECT_GT(held_weak, 0);
  bool warned = false;
  for (const auto& w : report.warnings) warned = warned || w.find("weakly identifiable") != std::string::npos;
  EXPECT_TRUE(warned);
}

// A fit stopped far from its minimum (one iteration from a start 20 mm off) still names every parameter the data
// determine worse than their reference where it stopped, and warns of those left free without a prior.
TEST(WeakParameters, AFitStoppedShortStillNamesItsWeakParameters) {
  const ToolOnAxisCase c = Irb120ToolOnAxis6();
  YAML::Node options(YAML::NodeType::Map);
  options["max_iterations"] = 1;
  Robot start = c.nominal;  // far from the truth: 20 mm and 50 mrad off on the arm's long rows
  for (const auto& [name, delta] : {std::pair<std::string, double>{"a_3", 0.02}, {"d_4", 0.02}, {"theta_3", 0.05}})
    start.model().SetParameter(name, start.model().Parameter(name) + delta);
  EstimationReport report;
  RunEstimator("least_squares", start, c.data, &report, options);
  std::cout << report.BriefReport() << "\n";
  EXPECT_EQ(report.status, EstimationStatus::kIterationLimit) << report.message;
  int weak = 0;
  for (const auto& p : report.parameters) {
    if (!p.free) continue;
    weak += p.weak;
    EXPECT_TRUE(p.weak || !(p.data_sd > ReferenceSd(p)) || ReferenceSd(p) == 0.0)
        << p.name << ": data sd " << p.data_sd << " above " << ReferenceSd(p) << " and not reported weak";
  }
  EXPECT_GT(weak, 0);
  bool warned = false;
  for (const auto& w : report.warnings)
    warned = warned || w.find("left free where the fit stopped") != std::string::npos;
  EXPECT_TRUE(warned);
}

// Options that take each error-model estimator to the minimum at rounding level.
YAML::Node TightOptions(const std::string& name) {
  YAML::Node o(YAML::NodeType::Map);
  o["prior"] = "on";
  if (name == "least_squares") {
    o["parameter_tolerance"] = 1e-14;
    o["function_tolerance"] = 0.0;
    o["max_iterations"] = 500;
  } else if (name == "ceres") {
    o["parameter_tolerance"] = 1e-16;
    o["function_tolerance"] = 1e-16;
    o["gradient_tolerance"] = 1e-16;
    o["max_iterations"] = 500;
  } else if (name == "nlopt") {
    o["function_tolerance"] = 0.0;
    o["parameter_tolerance"] = 1e-15;
    o["max_evaluations"] = 100000;
  } else if (name == "ipopt") {
    o["tolerance"] = 1e-14;
    o["max_iterations"] = 500;
  }
  return o;
}

// MAP on the UR grid: the four estimators reach the same estimate (1e-6 relative, against 1 mm or 1 mrad
// for values near zero), and the report gives prior sd, posterior sd and the data's share per parameter,
// consistent with each other: the posterior sd below both the data's and the prior's.
TEST(Priors, EveryErrorModelEstimatorReachesTheSameMapEstimate) {
  const Robot nominal = UrNominal();
  const Robot truth = UrTruth(nominal, 7);
  const Dataset data = UrGrid(truth, 100e-6, 11);
  EstimationReport reference;
  RunEstimator("least_squares", nominal, data, &reference, TightOptions("least_squares"));
  ASSERT_EQ(reference.status, EstimationStatus::kConverged) << reference.message;
  int with_prior = 0;
  for (const auto& p : reference.parameters) {
    if (!p.free || !std::isfinite(p.prior_sd)) continue;
    ++with_prior;
    EXPECT_GT(p.data_share, 0.0) << p.name;
    EXPECT_LT(p.data_share, 1.0) << p.name;
    EXPECT_LT(p.stddev, p.prior_sd) << p.name;
    EXPECT_LT(p.stddev, p.data_sd) << p.name;
    EXPECT_NEAR(p.data_share, 1.0 - (p.stddev * p.stddev) / (p.prior_sd * p.prior_sd), 1e-12) << p.name;
  }
  EXPECT_GT(with_prior, 10);
  // Every parameter the data determine worse than its prior is named weak, none is held for it.
  for (const auto& p : reference.parameters) {
    if (p.free && std::isfinite(p.prior_sd)) {
      EXPECT_EQ(p.weak, p.data_sd > p.prior_sd) << p.name;
    }
  }
  for (const std::string name : {"ceres", "nlopt", "ipopt"}) {
    if (!Estimators().IsRegistered(name)) continue;
    EstimationReport report;
    RunEstimator(name, nominal, data, &report, TightOptions(name));
    EXPECT_EQ(report.status, EstimationStatus::kConverged) << name << ": " << report.message;
    ASSERT_EQ(report.parameters.size(), reference.parameters.size());
    double worst = 0.0;
    for (size_t i = 0; i < report.parameters.size(); ++i) {
      const ParameterEstimate& a = reference.parameters[i];
      const ParameterEstimate& b = report.parameters[i];
      ASSERT_EQ(a.name, b.name);
      EXPECT_EQ(a.free, b.free) << name << " " << a.name;
      const double relative = std::abs(a.value - b.value) / std::max(std::abs(a.value), 1e-3);
      worst = std::max(worst, relative);
      // NLopt's quasi-Newton stops at roundoff along the flattest prior-dominated directions: 1e-7
      // relative in the gcc Release build, 7e-4 (7e-7 m on a_4) under clang -O1 with the sanitizers. There
      // it is held to a hundredth of the posterior standard deviation, statistically the same estimate.
      const bool same = relative <= 1e-6 || (name == "nlopt" && std::abs(a.value - b.value) <= 1e-2 * a.stddev);
      EXPECT_TRUE(same) << name << " " << a.name << ": " << a.value << " vs " << b.value << " (sd " << a.stddev << ")";
    }
    std::cout << name << ": largest relative difference to least_squares " << worst << "\n";
  }
}

// The prior pulls a parameter the data cannot see toward its start: with a prior map naming one
// parameter, its posterior sd stays at most its prior sd and a tighter prior keeps it closer.
TEST(Priors, ATighterPriorKeepsAWeakParameterCloserToItsStart) {
  const Robot nominal = UrNominal();
  const Robot truth = UrTruth(nominal, 7);
  const Dataset data = UrGrid(truth, 100e-6, 11);
  const auto alpha5 = [&](const std::string& sd) {
    YAML::Node o = YAML::Load("{prior: {alpha_5: " + sd + "}}");
    EstimationReport report;
    RunEstimator("least_squares", nominal, data, &report, o);
    for (const auto& p : report.parameters) {
      if (p.name == "alpha_5") {
        EXPECT_TRUE(p.free);
        EXPECT_LE(p.stddev, p.prior_sd * (1 + 1e-9));
        return std::abs(p.value - p.nominal);
      }
    }
    ADD_FAILURE() << "no alpha_5";
    return 0.0;
  };
  EXPECT_LT(alpha5("0.1mrad"), alpha5("20mrad"));
}

TEST(Priors, BadPriorOptionsAreOneLineErrors) {
  for (const char* bad :
       {"{prior: maybe}", "{prior: {length: 1parsec}}", "{prior: {length: -1mm}}", "{prior: [1, 2]}"}) {
    EXPECT_THROW(Estimators().Create("least_squares", YAML::Load(bad)), std::invalid_argument) << bad;
  }
  const Robot nominal = UrNominal();
  const Dataset data = UrGrid(UrTruth(nominal, 7), 100e-6, 11);
  EstimationReport report;
  EXPECT_THROW(RunEstimator("least_squares", nominal, data, &report, YAML::Load("{prior: {no_such: 1mm}}")),
               std::invalid_argument);
}

}  // namespace
}  // namespace kincal::testing
