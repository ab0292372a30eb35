// The shared error model: analytic Jacobians against central differences (every block: geometry, tool,
// ratios with and without encoders, markers, base, sessions, orientation), agreement with the spine's
// predictions, normal equations against a dense J, base registration, identifiability and the
// observability indices against a direct SVD.
#include <gtest/gtest.h>

#include "estimators/error_model/base_registration.h"
#include "estimators/error_model/error_model.h"
#include "estimators/error_model/pose_jacobians.h"
#include "estimators/error_model/start_placement.h"
#include "robot/prediction.h"
#include "framework/random.h"
#include "framework/svd.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::CentralDifference;

Eigen::Isometry3d RandomPose(Rng* rng, double reach) {
  const Eigen::Vector3d rpy(rng->Uniform(-M_PI, M_PI), rng->Uniform(-1.2, 1.2), rng->Uniform(-M_PI, M_PI));
  const Eigen::Vector3d xyz(rng->Uniform(-reach, reach), rng->Uniform(-reach, reach), rng->Uniform(-reach, reach));
  return PoseFromXyzRpy(xyz, rpy);
}

// The seed's arm with two markers, a tracker frame far away, sessions 0..2 and orientations on some rows:
// every block of the error model is present.
struct RichCase {
  Robot start, controller;
  Dataset data;
};

RichCase MakeRichCase(bool encoders) {
  RichCase c;
  c.controller = testing::SeedNominal();
  c.start = testing::SeedNominal();
  c.start.markers["A"] = Eigen::Vector3d(0.04, 0.03, 0.10);
  c.start.markers["B"] = Eigen::Vector3d(-0.05, 0.02, 0.08);
  Rng rng(7);
  c.start.model().SetBase(RandomPose(&rng, 2.0));
  c.start.session_bases[1] = RandomPose(&rng, 2.0);
  c.start.session_bases[2] = RandomPose(&rng, 2.0);
  // Perturb the chain so that nothing sits at a special value.
  Eigen::VectorXd v = c.start.model().Parameters();
  for (int j = 0; j < v.size(); ++j) v[j] += 0.01 * rng.Uniform(-1, 1);
  c.start.model().SetParameters(v);
  c.start.drives->ratio *= 1.003;

  c.data = testing::RandomPoses(c.controller, testing::SeedTruth(), 30, 3);
  const char* markers[3] = {"A", "B", ""};
  for (size_t i = 0; i < c.data.rows.size(); ++i) {
    Measurement& m = c.data.rows[i];
    m.marker = markers[i % 3];
    m.session = static_cast<int>(i / 3) % 3;
    m.p += Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    if (i % 2 == 0) m.orientation = Eigen::Quaterniond(RandomPose(&rng, 1.0).linear());
    if (!encoders) m.encoders.clear();
  }
  return c;
}

Eigen::VectorXd StackedResiduals(const ErrorModelProblem& problem, const Eigen::VectorXd& x) {
  auto ws = problem.NewWorkspace();
  Eigen::VectorXd out(problem.num_residuals());
  int k = 0;
  Vector6d r;
  for (int i = 0; i < problem.num_rows(); ++i) {
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, nullptr);
    out.segment(k, n) = r.head(n);
    k += n;
  }
  return out;
}

Eigen::MatrixXd StackedJacobian(const ErrorModelProblem& problem, const Eigen::VectorXd& x) {
  auto ws = problem.NewWorkspace();
  Eigen::MatrixXd out(problem.num_residuals(), problem.num_parameters());
  int k = 0;
  Vector6d r;
  Matrix6Xd J;
  for (int i = 0; i < problem.num_rows(); ++i) {
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, &J);
    out.middleRows(k, n) = J.topRows(n);
    k += n;
  }
  return out;
}

void ExpectJacobianMatchesCentralDifferences(const ErrorModelProblem& problem) {
  const Eigen::VectorXd x = problem.InitialX();
  const Eigen::MatrixXd J = StackedJacobian(problem, x);
  const Eigen::MatrixXd Jn =
      CentralDifference([&](const Eigen::VectorXd& y) { return StackedResiduals(problem, y); }, x, 1e-6);
  const auto names = problem.ParameterNames();
  for (int j = 0; j < problem.num_parameters(); ++j) {
    const double scale = std::max(1.0, Jn.col(j).cwiseAbs().maxCoeff());
    EXPECT_LT((J.col(j) - Jn.col(j)).cwiseAbs().maxCoeff(), 2e-7 * scale) << names[j];
  }
}

TEST(ErrorModelProblem, JacobianOfEveryBlockMatchesCentralDifferencesWithEncoders) {
  const RichCase c = MakeRichCase(true);
  const ErrorModelProblem problem(c.start, c.controller, c.data, ErrorModelOptions());
  // Every kind of block is present.
  std::set<std::string> blocks;
  for (const auto& b : problem.blocks()) blocks.insert(b.name);
  for (const char* name : {"geometry", "ratios", "marker:A", "marker:B", "base", "session:1", "session:2"}) {
    EXPECT_TRUE(blocks.count(name)) << name;
  }
  for (const char* name : {"tool_x", "tool_yaw", "ratio_3", "marker_B_z", "base_pitch", "session_2_roll"}) {
    const auto names = problem.ParameterNames();
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  EXPECT_GT(problem.num_residuals(), 3 * problem.num_rows());
  ExpectJacobianMatchesCentralDifferences(problem);
}

TEST(ErrorModelProblem, JacobianMatchesCentralDifferencesWithCommandedAnglesOnly) {
  const RichCase c = MakeRichCase(false);
  const ErrorModelProblem problem(c.start, c.controller, c.data, ErrorModelOptions());
  EXPECT_TRUE(problem.has_ratios());
  ExpectJacobianMatchesCentralDifferences(problem);
}

TEST(ErrorModelProblem, LeftJacobianInverseIsTheDerivativeOfTheLog) {
  Rng rng(11);
  for (double angle : {1e-7, 1e-3, 0.5, 2.0, 3.0}) {
    const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    const Eigen::Vector3d phi = angle * axis;
    const Eigen::Matrix3d E = RotationExp(phi);
    const Eigen::MatrixXd numeric =
        CentralDifference([&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return RotationLog(RotationExp(d) * E); },
                          Eigen::VectorXd::Zero(3), 1e-6);
    EXPECT_LT((LeftJacobianInverseSO3(phi) - numeric).cwiseAbs().maxCoeff(), 1e-8) << angle;
  }
}

TEST(ErrorModelProblem, WrittenRobotPredictsWhatTheResidualsSay) {
  const RichCase c = MakeRichCase(true);
  const ErrorModelProblem problem(c.start, c.controller, c.data, ErrorModelOptions());
  Eigen::VectorXd x = problem.InitialX();
  Rng rng(5);
  for (int i = 0; i < x.size(); ++i) x[i] += 1e-3 * rng.Uniform(-1, 1);
  Robot written;
  problem.WriteToRobot(x, &written);
  auto ws = problem.NewWorkspace();
  Vector6d r;
  for (int i = 0; i < problem.num_rows(); ++i) {
    problem.EvaluateRow(i, x, ws.get(), &r, nullptr);
    const Measurement& m = c.data.rows[i];
    const Eigen::Vector3d predicted = PredictMarker(c.controller, written, c.data, i, c.data.PreviousPoses());
    EXPECT_LT((predicted - m.p - r.head<3>()).norm(), 1e-12) << "row " << i;
  }
}

TEST(ErrorModelProblem, RowBlocksFollowSessionsAndMarkers) {
  const RichCase c = MakeRichCase(true);
  const ErrorModelProblem problem(c.start, c.controller, c.data, ErrorModelOptions());
  const Eigen::VectorXd x = problem.InitialX();
  auto ws = problem.NewWorkspace();
  Vector6d r;
  Matrix6Xd J;
  for (int i = 0; i < problem.num_rows(); ++i) {
    const int k = problem.EvaluateRow(i, x, ws.get(), &r, &J);
    std::vector<bool> touched(problem.num_parameters(), false);
    for (int b : problem.RowBlocks(i)) {
      for (int j = 0; j < problem.blocks()[b].size; ++j) touched[problem.blocks()[b].offset + j] = true;
    }
    for (int j = 0; j < problem.num_parameters(); ++j) {
      if (!touched[j]) {
        EXPECT_EQ(J.col(j).head(k).cwiseAbs().maxCoeff(), 0.0) << "row " << i << " column " << j;
      }
    }
  }
}

TEST(ErrorModelProblem, HoldsRedundantToolParametersByConstruction) {
  Robot nominal = testing::SeedNominal();
  nominal.markers["A"] = Eigen::Vector3d(0.04, 0.03, 0.1);
  Dataset data = testing::RandomPoses(nominal, nominal, 20);
  for (auto& m : data.rows) m.marker = "A";
  const ErrorModelProblem problem(nominal, nominal, data, ErrorModelOptions());
  std::map<std::string, std::string> held;
  for (const auto& h : problem.held()) held[h.parameter.name] = h.reason;
  for (const char* name : {"tool_x", "tool_y", "tool_z", "tool_roll", "tool_pitch", "tool_yaw"}) {
    EXPECT_NE(held[name].find("redundant with the marker offsets"), std::string::npos) << name;
  }
  EXPECT_EQ(held.size(), 6u);
}

TEST(ErrorModelProblem, NormalEquationsMatchTheDenseJacobian) {
  const RichCase c = MakeRichCase(true);
  const ErrorModelProblem problem(c.start, c.controller, c.data, ErrorModelOptions());
  const Eigen::VectorXd x = problem.InitialX();
  RowWeighting weighting;
  Rng rng(2);
  for (int i = 0; i < problem.num_rows(); ++i) weighting.weights.push_back(rng.Uniform(0.5, 2.0));
  const Eigen::MatrixXd J = StackedJacobian(problem, x);
  const Eigen::VectorXd r = StackedResiduals(problem, x);
  // Huber at the median row norm: half the rows beyond it.
  std::vector<double> norms;
  for (int i = 0, k = 0; i < problem.num_rows(); k += problem.RowResiduals(i), ++i) {
    norms.push_back(r.segment(k, problem.RowResiduals(i)).norm());
  }
  std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
  weighting.loss.type = RobustLoss::Type::kHuber;
  weighting.loss.scale = norms[norms.size() / 2];
  const NormalEquations ne = AccumulateNormalEquations(problem, x, weighting);

  Eigen::VectorXd w(r.size());
  double cost = 0.0;
  int k = 0, beyond = 0;
  for (int i = 0; i < problem.num_rows(); ++i) {
    const int n = problem.RowResiduals(i);
    const double s = r.segment(k, n).squaredNorm();
    double rho, rho1;
    weighting.loss.Evaluate(s, &rho, &rho1);
    beyond += rho1 < 1.0;
    cost += weighting.weights[i] * rho;
    w.segment(k, n).setConstant(weighting.weights[i] * rho1);
    k += n;
  }
  EXPECT_GT(beyond, 0);
  EXPECT_LT(beyond, problem.num_rows());
  const Eigen::MatrixXd JtJ = J.transpose() * w.asDiagonal() * J;
  const Eigen::VectorXd Jtr = J.transpose() * w.asDiagonal() * r;
  EXPECT_LT((ne.JtJ - JtJ).cwiseAbs().maxCoeff(), 1e-10 * JtJ.cwiseAbs().maxCoeff());
  EXPECT_LT((ne.Jtr - Jtr).cwiseAbs().maxCoeff(), 1e-10 * Jtr.cwiseAbs().maxCoeff());
  EXPECT_NEAR(ne.cost, cost, 1e-12 * cost);
  EXPECT_EQ(ne.num_residuals, problem.num_residuals());

  // Gradient of the cost is 2 J^T W r.
  const Eigen::MatrixXd g = CentralDifference(
      [&](const Eigen::VectorXd& y) {
        return Eigen::VectorXd::Constant(1, AccumulateNormalEquations(problem, y, weighting, Accumulate::kCost).cost);
      },
      x, 1e-7);
  EXPECT_LT((g.row(0).transpose() - 2.0 * ne.Jtr).cwiseAbs().maxCoeff(), 1e-5 * ne.Jtr.cwiseAbs().maxCoeff());
}

TEST(BaseRegistration, RecoversARigidTransformExactly) {
  Rng rng(4);
  const Eigen::Isometry3d T = RandomPose(&rng, 3.0);
  PointRegistration reg;
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d a(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    reg.Add(a, T * a);
  }
  Eigen::Isometry3d found;
  ASSERT_TRUE(reg.Solve(&found));
  EXPECT_LT((found.matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-13);

  PointRegistration line;
  for (int i = 0; i < 10; ++i) line.Add(Eigen::Vector3d(i, 2 * i, 0), T * Eigen::Vector3d(i, 2 * i, 0));
  EXPECT_FALSE(line.Solve(&found));
}

TEST(BaseRegistration, FindsTheTrackerFrameOfEachSession) {
  Robot truth = testing::SeedNominal();
  Rng rng(9);
  truth.model().SetBase(RandomPose(&rng, 3.0));
  truth.session_bases[4] = RandomPose(&rng, 3.0);
  Dataset data = testing::RandomPoses(truth, truth, 40);
  for (size_t i = 0; i < data.rows.size(); i += 2) {
    Measurement& m = data.rows[i];
    m.session = 4;
    const Eigen::VectorXd q = DriveAngles(truth, truth, m);
    m.p = PredictToolPose(truth, q, 4) * truth.MarkerPosition("");
  }
  Robot start = testing::SeedNominal();
  const StartPlacement placement = PlaceStart(truth, data, ErrorModelOptions(), &start);
  EXPECT_TRUE(placement.warnings.empty());
  EXPECT_LT((start.model().base().matrix() - truth.model().base().matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((start.session_bases.at(4).matrix() - truth.session_bases.at(4).matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

// Two reflectors a hand's width from the flange, the tracker metres away in two set-ups: with the chain
// exact, the closed-form placement recovers both bases and both reflectors from a start that knows
// neither (markers at the flange, identity bases), to rounding.
TEST(StartPlacement, RecoversBasesAndMarkersFromAStartThatKnowsNeither) {
  Robot truth = testing::SeedNominal();
  Rng rng(21);
  truth.model().SetBase(RandomPose(&rng, 3.0));
  truth.session_bases[2] = RandomPose(&rng, 3.0);
  truth.markers["A"] = Eigen::Vector3d(0.10, -0.05, 0.12);
  truth.markers["B"] = Eigen::Vector3d(-0.08, 0.02, 0.15);
  // Session 2 gets 30 rows: more than the 22 unknowns per coordinate of its rotation fit.
  Dataset data = testing::RandomPoses(truth, truth, 90);
  for (size_t i = 0; i < data.rows.size(); ++i) {
    Measurement& m = data.rows[i];
    m.marker = i % 2 ? "A" : "B";
    m.session = i % 3 ? 0 : 2;
    const Eigen::VectorXd q = DriveAngles(truth, truth, m);
    m.p = PredictToolPose(truth, q, m.session) * truth.MarkerPosition(m.marker);
  }
  Robot start = testing::SeedNominal();
  start.markers["A"] = start.markers["B"] = Eigen::Vector3d::Zero();
  const StartPlacement placement = PlaceStart(truth, data, ErrorModelOptions(), &start);
  EXPECT_TRUE(placement.warnings.empty()) << placement.warnings.front();
  EXPECT_LT(placement.rms, 1e-12);
  EXPECT_LT((start.model().base().matrix() - truth.model().base().matrix()).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((start.session_bases.at(2).matrix() - truth.session_bases.at(2).matrix()).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((start.markers.at("A") - truth.markers.at("A")).norm(), 1e-11);
  EXPECT_LT((start.markers.at("B") - truth.markers.at("B")).norm(), 1e-11);

  // A held reflector stays where the file puts it; the base is then registered on it.
  Robot held = testing::SeedNominal();
  held.markers["A"] = truth.markers.at("A");
  held.markers["B"] = Eigen::Vector3d::Zero();
  ErrorModelOptions options;
  options.fixed = {"marker_A_x"};
  PlaceStart(truth, data, options, &held);
  EXPECT_EQ(held.markers.at("A"), truth.markers.at("A"));
  EXPECT_LT((held.markers.at("B") - truth.markers.at("B")).norm(), 1e-11);
}

// Rows without a marker measure the tool origin: the placement sets the tool's translation.
TEST(StartPlacement, PlacesTheToolOrigin) {
  Robot truth = testing::SeedNominal();
  Rng rng(5);
  truth.model().SetBase(RandomPose(&rng, 2.0));
  Eigen::Isometry3d tool = truth.model().tool();
  tool.translation() += Eigen::Vector3d(0.03, -0.11, 0.09);
  truth.model().SetTool(tool);
  const Dataset data = testing::RandomPoses(truth, truth, 20);
  Robot start = testing::SeedNominal();
  const StartPlacement placement = PlaceStart(truth, data, ErrorModelOptions(), &start);
  EXPECT_LT(placement.rms, 1e-12);
  EXPECT_LT((start.model().tool().translation() - tool.translation()).norm(), 1e-11);
  EXPECT_LT((start.model().base().matrix() - truth.model().base().matrix()).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(Identifiability, SeedArmHoldsTheFirstRowAndTheLastOffsetAgainstTheTool) {
  const Robot nominal = testing::SeedNominal();
  const Dataset data = testing::RandomPoses(nominal, testing::SeedTruth(), 60);
  const PreparedErrorModel prep = PrepareErrorModel(nominal, nominal, data, ErrorModelOptions());
  const std::vector<std::string> expected = {"alpha_1", "a_1", "theta_1", "d_1", "theta_6", "d_6"};
  EXPECT_EQ(prep.identifiability.unidentifiable_names, expected);
  // Each names what it is redundant with.
  const auto& reasons = prep.identifiability.reasons;
  EXPECT_NE(reasons[2].find("base_yaw"), std::string::npos) << reasons[2];  // theta_1
  EXPECT_NE(reasons[3].find("base_z"), std::string::npos) << reasons[3];    // d_1
  EXPECT_NE(reasons[4].find("tool_x"), std::string::npos) << reasons[4];    // theta_6
  EXPECT_NE(reasons[5].find("tool_z"), std::string::npos) << reasons[5];    // d_6
  // 24 joint + 6 base + 3 tool positions + 6 ratios, minus the six above.
  EXPECT_EQ(prep.problem->num_parameters(), 33);
  EXPECT_GT(prep.identifiability.condition_number, 1.0);
  EXPECT_LT(prep.identifiability.condition_number, 1e4);
}

TEST(Identifiability, ParallelAxesHoldOneOfTheirOffsets) {
  // ABB IRB 120 (modified DH, data README): joints 2 and 3 parallel, so d_2 and d_3 move the arm alike.
  Robot irb = testing::LoadExampleRobot("irb120_mdh.yaml");
  irb.model().SetTool(PoseFromXyzRpy(Eigen::Vector3d(0.030, 0.020, 0.060), Eigen::Vector3d::Zero()));
  const Dataset data = testing::RandomPoses(irb, irb, 60);
  const PreparedErrorModel prep = PrepareErrorModel(irb, irb, data, ErrorModelOptions());
  const std::vector<std::string> expected = {"alpha_1", "a_1", "theta_1", "d_1", "d_3", "theta_6", "d_6"};
  EXPECT_EQ(prep.identifiability.unidentifiable_names, expected);
}

// The rule both re-analyses (the first solution, the prior-noise restarts) share, on a constructed analysis:
// the pattern of ur10_ipa2021 series A with priors (gravity coefficients freed, link geometry held) is refused;
// a change that only holds geometry, or frees a joint-level term against a base parameter, is not.
TEST(Identifiability, AReanalysisMayNotHandTheLinkGeometryToJointLevelTerms) {
  const auto parameter = [](const std::string& name, ErrorModelParameter::Group group) {
    ErrorModelParameter q;
    q.name = name;
    q.group = group;
    return q;
  };
  using G = ErrorModelParameter::Group;
  const std::vector<ErrorModelParameter> candidates = {parameter("a_2", G::kJoint), parameter("theta_3", G::kJoint),
                                                       parameter("gravity_2_link4", G::kJointError),
                                                       parameter("base_x", G::kBase)};
  const IdentifiabilityChange handed =
      CompareIdentifiability(candidates, {"gravity_2_link4", "base_x"}, {"base_x", "a_2", "theta_3"});
  EXPECT_EQ(handed.freed, " gravity_2_link4");
  EXPECT_EQ(handed.held, " a_2 theta_3");
  EXPECT_TRUE(handed.HandsGeometryToJointLevel());
  EXPECT_FALSE(CompareIdentifiability(candidates, {}, {"a_2"}).HandsGeometryToJointLevel());
  EXPECT_FALSE(CompareIdentifiability(candidates, {"gravity_2_link4"}, {"base_x"}).HandsGeometryToJointLevel());
  EXPECT_FALSE(CompareIdentifiability(candidates, {"a_2"}, {"gravity_2_link4"}).HandsGeometryToJointLevel());
  const IdentifiabilityChange none = CompareIdentifiability(candidates, {"a_2"}, {"a_2"});
  EXPECT_TRUE(none.freed.empty() && none.held.empty());
}

TEST(Identifiability, ObservabilityIndicesMatchADirectSvd) {
  const Robot nominal = testing::SeedNominal();
  const Dataset data = testing::RandomPoses(nominal, testing::SeedTruth(), 25);
  const PreparedErrorModel prep = PrepareErrorModel(nominal, nominal, data, ErrorModelOptions());
  const ErrorModelProblem& problem = *prep.problem;
  const Eigen::VectorXd x = problem.InitialX();
  const Eigen::MatrixXd J = StackedJacobian(problem, x);
  const Eigen::MatrixXd Jc = J * problem.CharacteristicScales().asDiagonal();
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(Jc).singularValues();
  const int L = static_cast<int>(s.size()), m = problem.num_rows();
  const IdentifiabilityAnalysis a = AnalyzeIdentifiability(problem, AccumulateNormalEquations(problem, x).JtJ, m, 1e-6);
  ASSERT_EQ(a.rank, L);
  const double o1 = std::pow(s.prod(), 1.0 / L) / std::sqrt(static_cast<double>(m));
  EXPECT_NEAR(a.observability.o1, o1, 1e-9 * o1);
  EXPECT_NEAR(a.observability.o2, s[L - 1] / s[0], 1e-6 * s[L - 1] / s[0]);
  EXPECT_NEAR(a.observability.o3, s[L - 1], 1e-6 * s[L - 1]);
  EXPECT_NEAR(a.observability.o4, s[L - 1] * s[L - 1] / s[0], 1e-6 * s[L - 1] * s[L - 1] / s[0]);
  EXPECT_NEAR(a.observability.o5, 1.0 / s.cwiseInverse().sum(), 1e-6 / s.cwiseInverse().sum());
  // Condition number of the column-normalised Jacobian.
  const Eigen::VectorXd norms = J.colwise().norm();
  const Eigen::VectorXd sn = Eigen::JacobiSVD<Eigen::MatrixXd>(J * norms.cwiseInverse().asDiagonal()).singularValues();
  EXPECT_NEAR(a.condition_number, sn[0] / sn[L - 1], 1e-6 * sn[0] / sn[L - 1]);
}

TEST(ErrorModelProblem, RejectsBadInputClearly) {
  const Robot nominal = testing::SeedNominal();
  Dataset data = testing::RandomPoses(nominal, nominal, 8);  // 24 residuals for 36 structurally free parameters
  try {
    ErrorModelProblem(nominal, nominal, data, ErrorModelOptions());
    ADD_FAILURE() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("too few measurements"), std::string::npos) << e.what();
  }
  data = testing::RandomPoses(nominal, nominal, 40);
  ErrorModelOptions options;
  options.fixed = {"a_9"};
  EXPECT_THROW(ErrorModelProblem(nominal, nominal, data, options), std::invalid_argument);
  Dataset unknown_marker = data;
  unknown_marker.rows[3].marker = "SMR7";
  EXPECT_THROW(ErrorModelProblem(nominal, nominal, unknown_marker, ErrorModelOptions()), std::invalid_argument);
  Dataset nan_orientation = data;
  nan_orientation.rows[2].orientation = Eigen::Quaterniond(NAN, 0, 0, 0);
  EXPECT_THROW(ErrorModelProblem(nominal, nominal, nan_orientation, ErrorModelOptions()), std::invalid_argument);
  Dataset nan_position = data;
  nan_position.rows[1].p.x() = NAN;
  EXPECT_THROW(ErrorModelProblem(nominal, nominal, nan_position, ErrorModelOptions()), std::invalid_argument);
  Dataset five_joints = data;
  five_joints.dof = 5;
  for (auto& m : five_joints.rows) m.q.conservativeResize(5);
  EXPECT_THROW(ErrorModelProblem(nominal, nominal, five_joints, ErrorModelOptions()), std::invalid_argument);
  options.fixed = {"base", "joint_1", "ratios", "tool"};
  const ErrorModelProblem fixed(nominal, nominal, data, options);
  for (const auto& p : fixed.parameters()) {
    EXPECT_NE(p.group, ErrorModelParameter::Group::kBase);
    EXPECT_NE(p.group, ErrorModelParameter::Group::kRatio);
    EXPECT_NE(p.joint, 0) << p.name;
  }
}

}  // namespace
}  // namespace kincal
