// Joint-level error regressors (models/joint_errors.h): every analytic derivative against central
// differences on every convention that supports them, the terms left out, and the gravity regressors
// against the gravity torque of point masses computed directly.
#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/joint_error_regressors.h"
#include "models/mdh_model.h"
#include "models/poe_model.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::CentralDifference;
using testing::RandomizedModel;
using T = JointErrorTerm::Type;

JointErrorTerm Term(T type, int joint, std::vector<int> orders = {}) {
  JointErrorTerm t;
  t.type = type;
  t.joint = joint;
  t.orders = std::move(orders);
  return t;
}

// Every type, on several joints.
JointErrors AllTypes(const KinematicModel& model) {
  JointErrors e;
  e.terms = {Term(T::kGravity, 1),  Term(T::kGravity, 2),  Term(T::kHarmonic, 0, {1, 2}), Term(T::kHarmonic, 3, {3}),
             Term(T::kBacklash, 0), Term(T::kBacklash, 4), Term(T::kApproach, 0),         Term(T::kApproach, 5)};
  e.Bind(model);
  return e;
}

struct Case {
  std::string label;
  std::function<std::unique_ptr<KinematicModel>()> make;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.label; }

class JointErrorRegressors : public ::testing::TestWithParam<Case> {};

TEST_P(JointErrorRegressors, DerivativesMatchCentralDifferences) {
  const auto model = RandomizedModel(GetParam().make(), 7);
  const JointErrors errors = AllTypes(*model);
  const Eigen::VectorXd v = (Eigen::VectorXd(6) << 2.0, 2.5, 3.0, 4.0, 5.0, 6.0).finished();
  JointErrorContext context;
  context.model = model.get();
  context.gravity = Eigen::Vector3d(0.1, -0.2, -1.0).normalized();
  context.velocity_limits = &v;
  Rng rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    Eigen::VectorXd qbar(6), previous(6);
    for (int i = 0; i < 6; ++i) qbar[i] = rng.Uniform(-3, 3), previous[i] = rng.Uniform(-3, 3);
    Eigen::MatrixXd d_qbar, d_previous, d_parameters;
    EvaluateRegressors(errors, context, qbar, &previous, {&d_qbar, &d_previous, &d_parameters});
    const auto at_qbar = [&](const Eigen::VectorXd& x) { return EvaluateRegressors(errors, context, x, &previous); };
    const auto at_previous = [&](const Eigen::VectorXd& x) { return EvaluateRegressors(errors, context, qbar, &x); };
    EXPECT_LT((d_qbar - CentralDifference(at_qbar, qbar)).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    EXPECT_LT((d_previous - CentralDifference(at_previous, previous)).cwiseAbs().maxCoeff(), 1e-8);
    auto copy = model->Clone();
    JointErrorContext moved = context;
    moved.model = copy.get();
    const auto at_parameters = [&](const Eigen::VectorXd& p) {
      copy->SetParameters(p);
      return EvaluateRegressors(errors, moved, qbar, &previous);
    };
    EXPECT_LT((d_parameters - CentralDifference(at_parameters, model->Parameters())).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST_P(JointErrorRegressors, MapDerivativesFollowTheCoefficients) {
  const auto model = RandomizedModel(GetParam().make(), 8);
  JointErrors errors = AllTypes(*model);
  Rng rng(3);
  Eigen::VectorXd c(errors.num_coefficients());
  for (int k = 0; k < c.size(); ++k) c[k] = rng.Uniform(-0.01, 0.01);
  errors.SetCoefficients(c);
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(6, 3.0);
  JointErrorContext context{model.get(), -Eigen::Vector3d::UnitZ(), &v};
  const Eigen::VectorXd qbar = (Eigen::VectorXd(6) << 0.3, -0.7, 1.1, 0.2, -1.3, 2.0).finished();
  const Eigen::VectorXd previous = (Eigen::VectorXd(6) << 0.1, -0.2, 0.5, 0.9, -1.0, 1.0).finished();
  JointErrorMap map;
  EvaluateJointErrorMap(errors, context, qbar, &previous, {true, true, true}, &map);
  const auto q_of = [&](const Eigen::VectorXd& x) {
    JointErrorMap m;
    EvaluateJointErrorMap(errors, context, x, &previous, {}, &m);
    return m.q;
  };
  EXPECT_LT((map.dq_dqbar - CentralDifference(q_of, qbar)).cwiseAbs().maxCoeff(), 1e-9);
  const auto q_of_previous = [&](const Eigen::VectorXd& x) {
    JointErrorMap m;
    EvaluateJointErrorMap(errors, context, qbar, &x, {}, &m);
    return m.q;
  };
  EXPECT_LT((map.dq_dprevious - CentralDifference(q_of_previous, previous)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((map.q - qbar - JointOffsets(errors, map.phi, 6)).norm(), 1e-15);
}

// The one-pass evaluation (models/joint_error_regressors.h) against EvaluateRegressors, which moves each
// gravity regressor along each twist on its own: regressors to the bit, derivatives to rounding; and its
// derivatives against central differences of its own regressors. Rows with and without a previous pose,
// with and without each derivative, one Row reused throughout (stale sizes must not leak between rows).
TEST_P(JointErrorRegressors, OnePassMatchesTheRegressorsOneByOne) {
  const auto model = RandomizedModel(GetParam().make(), 9);
  const JointErrors errors = AllTypes(*model);
  const Eigen::VectorXd v = (Eigen::VectorXd(6) << 2.0, 2.5, 3.0, 4.0, 5.0, 6.0).finished();
  const JointErrorContext context{model.get(), Eigen::Vector3d(0.3, 0.1, -1.0).normalized(), &v};
  const PreparedRegressors prepared(errors, *model);
  ASSERT_EQ(prepared.num_coefficients(), errors.num_coefficients());
  PreparedRegressors::Row row;
  Rng rng(17);
  for (int trial = 0; trial < 6; ++trial) {
    Eigen::VectorXd qbar(6), previous(6);
    for (int i = 0; i < 6; ++i) qbar[i] = rng.Uniform(-3, 3), previous[i] = rng.Uniform(-3, 3);
    const Eigen::VectorXd* prev = trial % 3 == 2 ? nullptr : &previous;
    const PreparedRegressors::Want want{trial != 1, trial % 2 == 0, trial != 3};
    Eigen::MatrixXd d_qbar, d_previous, d_parameters;
    const Eigen::VectorXd phi = EvaluateRegressors(errors, context, qbar, prev, {&d_qbar, &d_previous, &d_parameters});
    prepared.Evaluate(context, qbar, prev, want, &row);
    EXPECT_EQ(row.phi, phi) << "trial " << trial;
    const double scale = 1.0 + d_parameters.cwiseAbs().maxCoeff();
    if (want.qbar) {
      EXPECT_LT((row.d_qbar - d_qbar).cwiseAbs().maxCoeff(), 1e-14 * scale) << "trial " << trial;
    }
    if (want.previous) {
      EXPECT_EQ(row.d_previous, d_previous) << "trial " << trial;
    }
    if (want.parameters) {
      EXPECT_LT((row.d_parameters - d_parameters).cwiseAbs().maxCoeff(), 1e-14 * scale) << "trial " << trial;
    }
    if (!want.qbar || !want.parameters) continue;
    const auto at_qbar = [&](const Eigen::VectorXd& x) {
      PreparedRegressors::Row r;
      prepared.Evaluate(context, x, prev, {}, &r);
      return r.phi;
    };
    EXPECT_LT((row.d_qbar - CentralDifference(at_qbar, qbar)).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    auto copy = model->Clone();
    JointErrorContext moved = context;
    moved.model = copy.get();
    const auto at_parameters = [&](const Eigen::VectorXd& p) {
      copy->SetParameters(p);
      PreparedRegressors::Row r;
      prepared.Evaluate(moved, qbar, prev, {}, &r);
      return r.phi;
    };
    EXPECT_LT((row.d_parameters - CentralDifference(at_parameters, model->Parameters())).cwiseAbs().maxCoeff(), 1e-8);
  }
}

// The one-pass map is EvaluateJointErrorMap's: q to the bit, derivatives to rounding; and it refuses joint
// errors other than the ones prepared for.
TEST_P(JointErrorRegressors, OnePassMapMatchesTheMap) {
  const auto model = RandomizedModel(GetParam().make(), 10);
  JointErrors errors = AllTypes(*model);
  Rng rng(5);
  Eigen::VectorXd c(errors.num_coefficients());
  for (int k = 0; k < c.size(); ++k) c[k] = rng.Uniform(-0.01, 0.01);
  errors.SetCoefficients(c);
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(6, 3.0);
  const JointErrorContext context{model.get(), -Eigen::Vector3d::UnitZ(), &v};
  const Eigen::VectorXd qbar = (Eigen::VectorXd(6) << 0.4, -0.6, 1.2, 0.1, -1.1, 2.2).finished();
  const Eigen::VectorXd previous = (Eigen::VectorXd(6) << 0.2, -0.1, 0.4, 0.8, -1.2, 1.1).finished();
  JointErrorMap expected, map;
  EvaluateJointErrorMap(errors, context, qbar, &previous, {true, true, true}, &expected);
  const PreparedRegressors prepared(errors, *model);
  PreparedRegressors::Row row;
  prepared.EvaluateMap(errors, context, qbar, &previous, {true, true, true}, &row, &map);
  EXPECT_EQ(map.q, expected.q);
  EXPECT_EQ(map.phi, expected.phi);
  // Derivatives summed in another order: to rounding of their terms (coefficients 1e-2 times regressor
  // derivatives of order 1).
  EXPECT_LT((map.dq_dqbar - expected.dq_dqbar).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(map.dq_dprevious, expected.dq_dprevious);
  EXPECT_LT((map.dq_dparameters - expected.dq_dparameters).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_GT(expected.dq_dparameters.cwiseAbs().maxCoeff(), 1e-3);  // the comparison is not of zeros
  const Eigen::MatrixXd expected_parameters = expected.dq_dparameters;
  // A second row through the same scratch: no state carried over.
  const Eigen::VectorXd qbar2 = (Eigen::VectorXd(6) << -1.0, 0.3, -0.2, 1.5, 0.7, -2.0).finished();
  EvaluateJointErrorMap(errors, context, qbar2, nullptr, {true, false, true}, &expected);
  prepared.EvaluateMap(errors, context, qbar2, nullptr, {true, false, true}, &row, &map);
  EXPECT_EQ(map.q, expected.q);
  EXPECT_LT((map.dq_dqbar - expected.dq_dqbar).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((map.dq_dparameters - expected.dq_dparameters).cwiseAbs().maxCoeff(), 1e-15);
  // Only the parameter derivatives wanted (the fit's parameter Jacobian), through the scratch of a full
  // evaluation: the same q and parameter derivatives as the full evaluation's, and nothing else.
  JointErrorMap full, parameters_only;
  prepared.EvaluateMap(errors, context, qbar, &previous, {true, true, true}, &row, &full);
  prepared.EvaluateMap(errors, context, qbar, &previous, {false, false, true}, &row, &parameters_only);
  EXPECT_EQ(parameters_only.q, full.q);
  EXPECT_EQ(parameters_only.phi, full.phi);
  ASSERT_EQ(parameters_only.dq_dparameters.rows(), full.dq_dparameters.rows());
  ASSERT_EQ(parameters_only.dq_dparameters.cols(), full.dq_dparameters.cols());
  EXPECT_LT((parameters_only.dq_dparameters - full.dq_dparameters).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((parameters_only.dq_dparameters - expected_parameters).cwiseAbs().maxCoeff(), 1e-15);
  JointErrors other;
  other.terms = {Term(T::kBacklash, 0)};
  other.Bind(*model);
  EXPECT_THROW(prepared.EvaluateMap(other, context, qbar, &previous, {}, &row, &map), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Conventions, JointErrorRegressors,
                         ::testing::Values(Case{"mdh", [] { return std::make_unique<MdhModel>(6); }},
                                           Case{"dh", [] { return std::make_unique<DhModel>(6); }},
                                           Case{"hayati", [] { return std::make_unique<HayatiModel>(6); }},
                                           Case{"poe", [] { return std::make_unique<PoeModel>(6); }}),
                         [](const auto& info) { return info.param.label; });

TEST(JointErrors, TermsZeroEverywhereAreLeftOut) {
  MdhModel mdh(6);
  DhModel dh(6);
  JointErrors e;
  e.terms = {Term(T::kGravity, 1)};
  e.Bind(mdh);
  // Link 2 turns about its own z through its origin: only its x and y moments make a torque.
  EXPECT_EQ(e.terms[0].keys.front(), "link2_x");
  EXPECT_EQ(e.terms[0].keys.size(), 2u + 4u * 4u);
  EXPECT_EQ(e.CoefficientNames()[0], "gravity_2_link2_x");
  e.Bind(dh);
  EXPECT_EQ(e.terms[0].keys.front(), "link2");
  EXPECT_EQ(e.terms[0].keys.size(), 4u * 5u);
}

TEST(JointErrors, BindRefusesWhatItCannotModel) {
  MdhModel model(std::vector<JointType>{JointType::kRevolute, JointType::kPrismatic});
  const auto bind = [&](std::vector<JointErrorTerm> terms) {
    JointErrors e;
    e.terms = std::move(terms);
    e.Bind(model);
  };
  EXPECT_THROW(bind({Term(T::kGravity, 1)}), std::invalid_argument);           // prismatic
  EXPECT_THROW(bind({Term(T::kHarmonic, 0)}), std::invalid_argument);          // no orders
  EXPECT_THROW(bind({Term(T::kHarmonic, 0, {1, 1})}), std::invalid_argument);  // repeated order
  EXPECT_THROW(bind({Term(T::kBacklash, 2)}), std::invalid_argument);          // no joint 3
  EXPECT_THROW(bind({Term(T::kBacklash, 0), Term(T::kBacklash, 0)}), std::invalid_argument);
  EXPECT_NO_THROW(bind({Term(T::kBacklash, 1), Term(T::kApproach, 1)}));
}

// The regressors are the gravity torque of unknown masses written linearly: with the coefficients set to
// the masses and first moments of point masses, they reproduce z_i . sum_j (c_j - a_i) x (m_j g).
TEST(JointErrors, GravityRegressorsGiveTheTorqueOfPointMasses) {
  auto seed = testing::SeedNominal();
  const KinematicModel& model = seed.model();
  Rng rng(5);
  std::vector<double> mass(7);
  std::vector<Eigen::Vector3d> com(7);  // in frame j
  for (int j = 1; j <= 6; ++j)
    mass[j] = rng.Uniform(1, 20),
    com[j] = Eigen::Vector3d(rng.Uniform(-0.2, 0.2), rng.Uniform(-0.2, 0.2), rng.Uniform(-0.2, 0.2));
  const Eigen::Vector3d g_base(0.05, 0.1, -1.0);
  for (int i = 0; i < 6; ++i) {
    JointErrors e;
    e.terms = {Term(T::kGravity, i)};
    e.Bind(model);
    Eigen::VectorXd c(e.num_coefficients());
    for (size_t k = 0; k < e.terms[0].keys.size(); ++k) {
      const std::string& key = e.terms[0].keys[k];
      const int j = std::stoi(key.substr(4));
      const size_t us = key.find('_');
      c[static_cast<Eigen::Index>(k)] = us == std::string::npos ? mass[j] : mass[j] * com[j][key[us + 1] - 'x'];
    }
    e.SetCoefficients(c);
    JointErrorContext context{&model, g_base.normalized(), nullptr};
    const Eigen::VectorXd q = (Eigen::VectorXd(6) << 0.4, 1.9, -0.3, 0.8, -1.1, 0.6).finished();
    const double regressed = JointOffsets(e, EvaluateRegressors(e, context, q, nullptr), 6)[i];
    const auto frames = model.FramePoses(q);
    const Eigen::Vector3d z = frames[i + 1].linear().col(2), a = frames[i + 1].translation();
    const Eigen::Vector3d g = frames[0].linear() * g_base.normalized();
    double torque = 0.0;
    for (int j = i + 1; j <= 6; ++j) torque += z.dot((frames[j] * com[j] - a).cross(mass[j] * g));
    EXPECT_NEAR(regressed, torque, 1e-12 * (1 + std::abs(torque))) << "joint " << i + 1;
  }
}

// A coefficient's kind is the dimension of its regressor: an arm twice as large (every length doubled)
// doubles the gravity link<j> regressors (a lever arm: coefficient in rad/m) and leaves the others as
// they are (rad); approach regressors are speeds in rad/s (coefficient in s).
TEST(JointErrors, CoefficientKindsAreTheRegressorsDimensions) {
  using Kind = JointErrorTerm::CoefficientKind;
  const auto model = RandomizedModel(std::make_unique<MdhModel>(6), 31);
  auto doubled = model->Clone();
  Eigen::VectorXd p = model->Parameters();
  for (int i = 0; i < p.size(); ++i) {
    if (model->parameter_info()[i].kind == ParameterInfo::Kind::kLength) p[i] *= 2;
  }
  doubled->SetParameters(p);
  const JointErrors e = AllTypes(*model);
  const Eigen::VectorXd v = (Eigen::VectorXd(6) << 1, 1, 1, 2, 2, 2).finished();
  const JointErrorContext context{model.get(), -Eigen::Vector3d::UnitZ(), &v};
  const JointErrorContext context2{doubled.get(), -Eigen::Vector3d::UnitZ(), &v};
  const Eigen::VectorXd q = (Eigen::VectorXd(6) << 0.4, 1.9, -0.3, 0.8, -1.1, 0.6).finished();
  const Eigen::VectorXd from = (Eigen::VectorXd(6) << 0.1, 1.2, 0.3, 0.8, -0.2, 0.9).finished();
  const Eigen::VectorXd phi = EvaluateRegressors(e, context, q, &from);
  const Eigen::VectorXd phi2 = EvaluateRegressors(e, context2, q, &from);
  const std::vector<Kind> kinds = e.CoefficientKinds();
  const std::vector<std::string> names = e.CoefficientNames();
  ASSERT_EQ(kinds.size(), static_cast<size_t>(phi.size()));
  int counted[3] = {0, 0, 0};
  for (int k = 0; k < phi.size(); ++k) {
    const double factor = kinds[k] == Kind::kAnglePerLength ? 2.0 : 1.0;
    EXPECT_NEAR(phi2[k], factor * phi[k], 1e-12 * (1 + std::abs(phi[k]))) << names[k];
    ++counted[static_cast<int>(kinds[k])];
    EXPECT_EQ(kinds[k] == Kind::kTime, names[k].rfind("approach_", 0) == 0) << names[k];
  }
  for (int c : counted) EXPECT_GT(c, 0);  // every kind is exercised
}

TEST(JointErrors, BacklashAndApproachNeedAMove) {
  MdhModel model(3);
  JointErrors e;
  e.terms = {Term(T::kBacklash, 1), Term(T::kApproach, 2)};
  e.Bind(model);
  const Eigen::Vector3d v(1.0, 2.0, 4.0);
  const Eigen::VectorXd limits = v;
  JointErrorContext context{&model, -Eigen::Vector3d::UnitZ(), &limits};
  const Eigen::VectorXd q = Eigen::Vector3d(0.1, 0.2, 0.3);
  EXPECT_EQ(EvaluateRegressors(e, context, q, nullptr), Eigen::Vector2d::Zero());
  EXPECT_EQ(EvaluateRegressors(e, context, q, &q), Eigen::Vector2d::Zero());
  // From (0, 0.4, 0.3): joint 2 moves -0.2 at 2 rad/s (0.1 s), joint 1 +0.1 at 1 rad/s (0.1 s): a tie;
  // joint 3 does not move, so its speed is 0; backlash of joint 2 is -1.
  const Eigen::VectorXd from = Eigen::Vector3d(0.0, 0.4, 0.3);
  const Eigen::VectorXd phi = EvaluateRegressors(e, context, q, &from);
  EXPECT_EQ(phi[0], -1.0);
  EXPECT_EQ(phi[1], 0.0);
  const Eigen::VectorXd from3 = Eigen::Vector3d(0.1, 0.2, -0.5);  // only joint 3 moves: 0.8 rad in 0.2 s
  EXPECT_NEAR(EvaluateRegressors(e, context, q, &from3)[1], 4.0, 1e-15);
  context.velocity_limits = nullptr;
  EXPECT_THROW(EvaluateRegressors(e, context, q, &from3), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
