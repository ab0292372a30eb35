// Joint-level errors in the error model: the analytic Jacobian with every joint error type
// against central differences, and exact recovery of a truth that has them from noise-free data by all
// four error-model estimators (efficiency: joint_error_efficiency_test.cc).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "estimators/error_model/error_model.h"
#include "framework/random.h"
#include "robot/joint_readings.h"
#include "tests/estimators/joint_error_fixture.h"

namespace kincal::testing {
namespace {

Eigen::VectorXd Residuals(const ErrorModelProblem& problem, const Eigen::VectorXd& x) {
  auto ws = problem.NewWorkspace();
  Eigen::VectorXd out(problem.num_residuals());
  Vector6d r;
  for (int i = 0, k = 0; i < problem.num_rows(); ++i) {
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, nullptr);
    out.segment(k, n) = r.head(n);
    k += n;
  }
  return out;
}

void ExpectJacobianMatches(const ErrorModelProblem& problem) {
  const Eigen::VectorXd x = problem.InitialX();
  auto ws = problem.NewWorkspace();
  Eigen::MatrixXd J(problem.num_residuals(), problem.num_parameters());
  Vector6d r;
  Matrix6Xd Jr;
  for (int i = 0, k = 0; i < problem.num_rows(); ++i) {
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, &Jr);
    J.middleRows(k, n) = Jr.topRows(n);
    k += n;
  }
  const Eigen::VectorXd h = problem.CharacteristicScales() * 1e-3;
  const auto names = problem.ParameterNames();
  for (int j = 0; j < problem.num_parameters(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += h[j];
    xm[j] -= h[j];
    const Eigen::VectorXd numeric = (Residuals(problem, xp) - Residuals(problem, xm)) / (2 * h[j]);
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    EXPECT_LT((J.col(j) - numeric).cwiseAbs().maxCoeff(), 1e-6 * scale) << names[j];
  }
}

TEST(JointErrorModel, JacobianMatchesCentralDifferencesForEveryType) {
  for (bool encoders : {true, false}) {
    JointErrorCase c = MakeCase(40, 5);
    Robot start = c.nominal;
    RandomCoefficients(&start, 9);  // derivatives at non-zero coefficients
    start.drives->ratio *= 1.002;
    start.markers["A"] = Eigen::Vector3d(0.04, 0.03, 0.1);
    Rng rng(3);
    for (size_t i = 0; i < c.data.rows.size(); ++i) {
      Measurement& m = c.data.rows[i];
      if (i % 3 == 0) m.marker = "A";
      if (i % 4 == 1) m.session = 1;
      if (i % 2 == 0)
        m.orientation =
            Eigen::Quaterniond(PoseFromXyzRpy(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.2, i)).linear());
      if (!encoders) m.encoders.clear();
    }
    start.session_bases[1] = PoseFromXyzRpy(Eigen::Vector3d(1, 2, 0.5), Eigen::Vector3d(0.1, 0.2, 0.3));
    const ErrorModelProblem problem(start, c.nominal, c.data, ErrorModelOptions());
    std::set<std::string> blocks;
    for (const auto& b : problem.blocks()) blocks.insert(b.name);
    EXPECT_TRUE(blocks.count("joint_errors") && blocks.count("ratios") && blocks.count("geometry"));
    SCOPED_TRACE(encoders ? "with encoders" : "commanded angles only");
    ExpectJacobianMatches(problem);
  }
}

// On an arm with parallel axes 2 and 3 (the IRB 120, alpha_3 = 0), joint 2's gravity term of frame 3's z
// axis, z_2 . (z_3 x g), is zero at every pose; computed, it is rounding (1e-17). Normalised by that RMS,
// its column of rounding noise once passed as an independent effect: kept as identifiable, its coefficient
// ran to 1e10 and pulled alpha_3 with it (on the real IRB 120, reflector 3 alone stalled at 0.89 mm).
TEST(JointErrorModel, ARegressorThatIsZeroByGeometryHasNoEffect) {
  Robot nominal = LoadExampleRobot("irb120_mdh.yaml");
  for (int joint : {1, 2}) {
    JointErrorTerm t;
    t.type = T::kGravity;
    t.joint = joint;
    nominal.joint_errors.terms.push_back(t);
  }
  nominal.joint_errors.Bind(nominal.model());
  Robot truth = nominal;
  truth.model().SetBase(TrackerBase());
  const Dataset data = RandomPoses(nominal, truth, 100, 4);
  const PreparedErrorModel prep = PrepareErrorModel(nominal, nominal, data, ErrorModelOptions());
  const IdentifiabilityAnalysis& a = prep.identifiability;
  const auto held = std::find(a.unidentifiable_names.begin(), a.unidentifiable_names.end(), "gravity_2_link3_z");
  ASSERT_NE(held, a.unidentifiable_names.end());
  EXPECT_EQ(a.reasons[static_cast<size_t>(held - a.unidentifiable_names.begin())],
            "not identifiable: no effect on the measurements");
  // The terms the arm's masses do make stay: joint 2's own link and the forearm's.
  for (const char* kept : {"gravity_2_link2_x", "gravity_2_link2_y", "gravity_2_link3_x", "gravity_3_link3_y"}) {
    EXPECT_EQ(std::count(a.unidentifiable_names.begin(), a.unidentifiable_names.end(), kept), 0) << kept;
  }
}

// Terms held whole at zero add nothing (equation 1 of models/joint_errors.h), so the problem leaves them
// out: residuals and Jacobian equal, to the last bit, those of the same robot without the terms, at the
// start and away from it (ratios and geometry moved, the chain rule through the joint angles exercised).
TEST(JointErrorModel, TermsHeldAtZeroGiveTheProblemWithoutThem) {
  const JointErrorCase c = MakeCase(40, 5);
  Robot without = c.nominal;
  without.joint_errors.terms.clear();
  ErrorModelOptions fixed;
  fixed.fixed = {"joint_errors"};
  const ErrorModelProblem held(c.nominal, c.nominal, c.data, fixed);
  const ErrorModelProblem plain(without, c.nominal, c.data, ErrorModelOptions());
  ASSERT_EQ(held.ParameterNames(), plain.ParameterNames());
  Eigen::VectorXd moved = held.InitialX();
  Rng rng(8);
  for (int j = 0; j < moved.size(); ++j) moved[j] += rng.Uniform(-1, 1) * held.CharacteristicScales()[j];
  for (const Eigen::VectorXd& x : {held.InitialX(), moved}) {
    auto ws_held = held.NewWorkspace(), ws_plain = plain.NewWorkspace();
    Vector6d r_held, r_plain;
    Matrix6Xd J_held, J_plain;
    for (int i = 0; i < held.num_rows(); ++i) {
      ASSERT_EQ(held.EvaluateRow(i, x, ws_held.get(), &r_held, &J_held),
                plain.EvaluateRow(i, x, ws_plain.get(), &r_plain, &J_plain));
      ASSERT_TRUE(r_held == r_plain) << "row " << i;
      ASSERT_TRUE(J_held == J_plain) << "row " << i;
    }
  }
}

// A term held at NON-zero coefficients still moves its joint: with the truth as the start, everything
// held that the truth has (the noise-free data come from it), the residuals vanish; with the same terms
// held at zero they do not (the terms matter to these data).
TEST(JointErrorModel, TermsHeldAtNonZeroCoefficientsStillShiftThePrediction) {
  JointErrorCase c = MakeCase(40, 5);
  ErrorModelOptions options;
  options.initialize_bases = false;
  for (const std::vector<std::string>& fixed :
       std::vector<std::vector<std::string>>{{"joint_errors"}, {"gravity"}, {"harmonic", "backlash", "approach"}}) {
    options.fixed = fixed;
    const ErrorModelProblem truth(c.truth, c.nominal, c.data, options);
    EXPECT_LT(Residuals(truth, truth.InitialX()).cwiseAbs().maxCoeff(), 1e-12) << fixed[0];
  }
  Robot zero = c.truth;
  zero.joint_errors.SetCoefficients(Eigen::VectorXd::Zero(zero.joint_errors.num_coefficients()));
  options.fixed = {"joint_errors"};
  const ErrorModelProblem without(zero, c.nominal, c.data, options);
  EXPECT_GT(Residuals(without, without.InitialX()).cwiseAbs().maxCoeff(), 1e-5);
}

// The same for a robot's predictions (robot/joint_readings.h): terms whose coefficients are all zero are
// not evaluated, and the actual angles equal, bit for bit, those of the robot without them; the terms
// left (non-zero) still move the joints.
TEST(JointErrorModel, ActualAnglesOfARobotWithZeroTermsAreThoseWithoutThem) {
  const JointErrorCase c = MakeCase(40, 5);
  Robot some_zero = c.truth, acting = c.truth;
  acting.joint_errors.terms.clear();
  for (JointErrorTerm& t : some_zero.joint_errors.terms) {
    if (t.type == T::kGravity || t.type == T::kApproach)
      t.coefficients.setZero();
    else
      acting.joint_errors.terms.push_back(t);
  }
  Robot all_zero = some_zero, none = c.truth;
  for (JointErrorTerm& t : all_zero.joint_errors.terms) t.coefficients.setZero();
  none.joint_errors.terms.clear();
  const auto previous = c.data.PreviousPoses();
  double moved = 0.0;
  for (size_t i = 0; i < c.data.rows.size(); ++i) {
    const Eigen::VectorXd q = ActualJointAngles(c.nominal, some_zero, c.data, i, previous);
    ASSERT_TRUE(q == ActualJointAngles(c.nominal, acting, c.data, i, previous)) << "row " << i;
    const Eigen::VectorXd qbar = ActualJointAngles(c.nominal, none, c.data, i, previous);
    ASSERT_TRUE(ActualJointAngles(c.nominal, all_zero, c.data, i, previous) == qbar) << "row " << i;
    moved = std::max(moved, (q - qbar).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(moved, 1e-5);  // rad: harmonic and backlash terms of about 0.03 deg
}

class JointErrorRecovery : public ErrorModelEstimatorTest {};

TEST_P(JointErrorRecovery, NoiseFreeDataGiveTheTruthExactly) {
  const JointErrorCase c = MakeCase(150, 21);
  ASSERT_GE(c.identifiable.size(), 20u);  // most terms are separable from 150 random poses
  EstimationReport report;
  const Robot identified = Run(c.data, c.nominal, &report);
  ASSERT_NE(report.status, EstimationStatus::kFailed) << report.BriefReport();
  int checked = 0;
  for (const auto& name : c.identifiable) {
    const auto it = std::find_if(report.parameters.begin(), report.parameters.end(),
                                 [&](const ParameterEstimate& p) { return p.name == name; });
    ASSERT_NE(it, report.parameters.end()) << name;
    const double truth = TruthCoefficient(c.truth, name);
    EXPECT_NEAR(it->value, truth, 1e-9 * std::abs(truth)) << name;
    EXPECT_NEAR(TruthCoefficient(identified, name), truth, 1e-9 * std::abs(truth)) << name;
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(c.identifiable.size()));
  // Held-out poses of the same program: predicted to rounding.
  const Dataset test = RandomPoses(c.nominal, c.truth, 50, 99);
  EXPECT_LT(EvaluatePredictions(c.nominal, identified, test).position_stats.max, 1e-11);
  std::printf("%s: %zu of %d joint error coefficients identifiable; %s\n", GetParam().c_str(), c.identifiable.size(),
              c.truth.joint_errors.num_coefficients(), report.BriefReport().c_str());
}

INSTANTIATE_TEST_SUITE_P(Estimators, JointErrorRecovery, ::testing::ValuesIn(kErrorModelEstimators));

}  // namespace
}  // namespace kincal::testing
