// Model selection (estimators/selection/model_selection.h): the nested candidates in the documented order,
// the blocked folds, the one-standard-error rule, and on simulated data the choice between a model the
// data need and one they do not.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "robot/prediction.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

// The coefficients a candidate frees: its terms' names less the ones it holds.
std::set<std::string> FreeCoefficients(const Robot& robot, const SelectionCandidate& c) {
  std::set<std::string> out;
  const Robot r = CandidateRobot(robot, c);
  for (const std::string& name : r.joint_errors.CoefficientNames()) {
    if (std::find(c.held.begin(), c.held.end(), name) == c.held.end()) out.insert(name);
  }
  return out;
}

TEST(NestedCandidates, GeometryThenCompliancesThenTypeThenJointEachAddingOneGroup) {
  const Robot robot = LoadExampleRobot("irb120_joint_errors.yaml");  // gravity 2-5, approach 1-6
  const std::vector<SelectionCandidate> c = NestedCandidates(robot);
  ASSERT_EQ(c.size(), 15u);
  EXPECT_EQ(c[0].name, "geometry");
  EXPECT_TRUE(c[0].terms.empty());
  EXPECT_EQ(c[1].name, "+ compliance 2");
  EXPECT_EQ(FreeCoefficients(robot, c[1]), std::set<std::string>{"gravity_2_link6"});
  EXPECT_EQ(c[4].name, "+ compliance 5");
  EXPECT_EQ(FreeCoefficients(robot, c[4]).size(), 4u);  // one per joint
  EXPECT_EQ(c[5].name, "+ gravity 2");
  EXPECT_EQ(c[8].name, "+ gravity 5");
  EXPECT_TRUE(c[8].held.empty());
  EXPECT_EQ(c[9].name, "+ approach 1");
  EXPECT_EQ(c[14].name, "+ approach 6");
  for (size_t i = 1; i < c.size(); ++i) {  // nested: each frees what the one before does, and more
    const std::set<std::string> before = FreeCoefficients(robot, c[i - 1]), now = FreeCoefficients(robot, c[i]);
    EXPECT_GT(now.size(), before.size()) << c[i].name;
    for (const auto& name : before) EXPECT_TRUE(now.count(name)) << c[i].name << " " << name;
  }
  EXPECT_EQ(CandidateRobot(robot, c.back()).joint_errors.terms.size(), robot.joint_errors.terms.size());
  EXPECT_TRUE(CandidateRobot(robot, c[0]).joint_errors.empty());
}

TEST(BlockedFolds, ContiguousBalancedBlocksWithinEverySession) {
  Dataset data;
  data.dof = 1;
  for (int i = 0; i < 23; ++i) {
    Measurement m;
    m.q = Eigen::VectorXd::Zero(1);
    m.session = i < 13 ? 0 : 2;  // 13 rows of session 0, then 10 of session 2
    data.rows.push_back(m);
  }
  const std::vector<int> fold = BlockedFolds(data, 5);
  for (int session : {0, 2}) {
    std::vector<int> f;
    for (size_t i = 0; i < data.rows.size(); ++i)
      if (data.rows[i].session == session) f.push_back(fold[i]);
    for (size_t i = 1; i < f.size(); ++i) EXPECT_GE(f[i], f[i - 1]);  // contiguous, in order
    for (int k = 0; k < 5; ++k) {
      const auto n = std::count(f.begin(), f.end(), k);
      EXPECT_GE(n, static_cast<long>(f.size() / 5));
      EXPECT_LE(n, static_cast<long>(f.size() / 5 + 1));
    }
  }
}

TEST(OneStandardErrorChoice, SimplestWithinOneSeOfTheBest) {
  std::vector<CandidateScore> s(4);
  const double cv[] = {1.00, 0.80, 0.70, 0.72}, se[] = {0.05, 0.05, 0.05, 0.20};
  for (int i = 0; i < 4; ++i) s[i].cv_rms = cv[i], s[i].se = se[i];
  EXPECT_EQ(OneStandardErrorChoice(s), 2);  // best 0.70 + 0.05: 0.80 is outside, 0.72 more complex
  s[1].cv_rms = 0.74;
  EXPECT_EQ(OneStandardErrorChoice(s), 1);
  s[0].cv_rms = NAN;
  s[1].cv_rms = 0.69;
  EXPECT_EQ(OneStandardErrorChoice(s), 1);
}

// Every fold is harder or easier for all candidates alike: the paired rule sees a consistent excess
// that each candidate's own se (over 0.6 here) hides.
TEST(PairedStandardErrorChoice, SimplestWhoseFoldWiseExcessIsWithinItsSe) {
  std::vector<CandidateScore> s(3);
  const std::vector<double> best = {1.0, 2.0, 3.0, 4.0, 5.0};
  for (size_t k = 0; k < best.size(); ++k) {
    s[0].fold_rms.push_back(best[k] + 0.1);                   // always 0.1 worse
    s[1].fold_rms.push_back(best[k] + (k % 2 ? -0.02 : 0.02));  // 0.004 worse on average, noisily
    s[2].fold_rms.push_back(best[k]);
  }
  for (auto& c : s) {
    double mean = 0.0;
    for (double r : c.fold_rms) mean += r / 5;
    c.cv_rms = mean;
    c.se = 0.7;
  }
  EXPECT_EQ(OneStandardErrorChoice(s), 0);  // every candidate's se swamps the differences
  EXPECT_EQ(PairedStandardErrorChoice(&s), 1);
  EXPECT_NEAR(s[0].excess_se, 0.0, 1e-12);
  // var of (0.02, -0.02, 0.02, -0.02, 0.02) = 4.8e-4; times 1/5 + 1/4
  EXPECT_NEAR(s[1].excess_se, std::sqrt(4.8e-4 * 0.45), 1e-12);
  for (double& r : s[1].fold_rms) r += 0.1;  // now 0.104 worse, se 0.015: only the best is left
  s[1].cv_rms += 0.1;
  EXPECT_EQ(PairedStandardErrorChoice(&s), 2);
}

// Simulated IRB 120-like arm: the truth has gravity compliance of joint 2 (or none); the robot file
// declares gravity 2, 3 and approach 1. Selection must keep gravity 2 when it is there and choose
// geometry when nothing beyond it is there.
Dataset Simulate(const Robot& truth, int rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::normal_distribution<double> noise(0.0, 20e-6);
  Dataset data;
  data.dof = truth.dof();
  for (int i = 0; i < rows; ++i) {
    Measurement m;
    m.q = Eigen::VectorXd(truth.dof());
    for (int j = 0; j < truth.dof(); ++j) m.q[j] = u(rng);
    data.rows.push_back(m);
  }
  const std::vector<Eigen::Vector3d> p = PredictMarkers(truth, truth, data);
  for (int i = 0; i < rows; ++i) data.rows[i].p = p[i] + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  return data;
}

Robot WithTerms(Robot robot, const std::vector<std::pair<JointErrorTerm::Type, int>>& terms) {
  robot.velocity_limits = Eigen::VectorXd::Constant(robot.dof(), 4.0);
  robot.joint_errors.terms.clear();
  for (const auto& [type, joint] : terms) {
    JointErrorTerm t;
    t.type = type;
    t.joint = joint;
    robot.joint_errors.terms.push_back(t);
  }
  robot.joint_errors.Bind(robot.model());
  return robot;
}

std::string SelectedModel(const Robot& declared, const Dataset& data) {
  YAML::Node options;
  options["select"] = true;
  options["max_iterations"] = 100;
  Robot identified;
  const EstimationReport report = Estimators().Create("least_squares", options)->Estimate(declared, data, &identified);
  return ChosenCandidate(report.details.at("selection"));
}

TEST(ModelSelection, KeepsTheTermTheDataNeedAndDropsTheOnesTheyDoNot) {
  using T = JointErrorTerm::Type;
  const Robot nominal = LoadExampleRobot("irb120_mdh.yaml");
  const Robot declared = WithTerms(nominal, {{T::kGravity, 1}, {T::kGravity, 2}, {T::kApproach, 0}});
  Robot truth = WithTerms(nominal, {{T::kGravity, 1}});
  Eigen::VectorXd c = truth.joint_errors.Coefficients();
  c.setConstant(2e-3);  // a few mrad of compliance: far above the 20 um noise
  truth.joint_errors.SetCoefficients(c);
  const std::string with_gravity = SelectedModel(declared, Simulate(truth, 300, 1));
  EXPECT_TRUE(with_gravity == "+ gravity 2" || with_gravity == "+ gravity 3" || with_gravity == "+ approach 1")
      << with_gravity;
  EXPECT_EQ(SelectedModel(declared, Simulate(WithTerms(nominal, {}), 300, 2)), "geometry");
}

}  // namespace
}  // namespace kincal::testing
