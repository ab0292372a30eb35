// Every measurement kind through the error model, on simulated rows of the seed's arm whose truth is
// known: the problem's Jacobian over every kind and fixture block against central differences, what
// identifiability holds for distances and for one plane, and recovery of the arm from distances to
// unknown pivots.
#include <cstdio>
#include <functional>
#include <map>

#include <gtest/gtest.h>

#include "estimators/error_model/error_model.h"
#include "estimators/estimator.h"
#include "framework/random.h"
#include "robot/instrument_scoring.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::CentralDifference;

struct KindsCase {
  Robot nominal, truth;
  Dataset data;  // commanded angles only (no encoders): a row's joints can be moved to touch a fixture
};

KindsCase RandomCase(int poses, uint64_t seed) {
  KindsCase c;
  c.nominal = testing::SeedNominal();
  c.truth = testing::SeedTruth();
  c.truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(1.8, -0.6, 0.4), Eigen::Vector3d(0.3, -0.2, 2.0)));
  c.data = testing::RandomPoses(c.nominal, c.truth, poses, seed);
  for (Measurement& m : c.data.rows) m.encoders.clear();
  const std::vector<Eigen::Vector3d> p = PredictMarkers(c.nominal, c.truth, c.data);
  for (size_t i = 0; i < c.data.rows.size(); ++i) c.data.rows[i].p = p[i];
  return c;
}

bool WithinLimits(const Robot& robot, const Eigen::VectorXd& q) {
  for (int i = 0; i < q.size(); ++i) {
    const double low = robot.limits.empty() ? -M_PI / 2 : robot.limits[i].first;
    const double high = robot.limits.empty() ? M_PI / 2 : robot.limits[i].second;
    if (!(q[i] >= low && q[i] <= high)) return false;
  }
  return true;
}

// Moves joints 1..3 of row i (Gauss-Newton, numerical derivatives) until g(truth's marker) = 0.
bool Touch(const KindsCase& c, Dataset* data, size_t i,
           const std::function<Eigen::VectorXd(const Eigen::Vector3d&)>& g) {
  Measurement& m = data->rows[i];
  for (int iteration = 0; iteration < 30; ++iteration) {
    const auto residual = [&](const Eigen::VectorXd& q3) {
      const Eigen::VectorXd saved = m.q;
      m.q.head<3>() = q3;
      const Eigen::VectorXd r = g(PredictMarker(c.nominal, c.truth, *data, i, data->PreviousPoses()));
      m.q = saved;
      return r;
    };
    const Eigen::VectorXd q3 = m.q.head<3>();
    const Eigen::VectorXd r = residual(q3);
    if (r.norm() < 1e-13) return true;
    const Eigen::MatrixXd J = CentralDifference(residual, q3, 1e-7);
    m.q.head<3>() -= J.completeOrthogonalDecomposition().solve(r);
  }
  return false;
}

// Pivots about 0.7 m from the base (the truth's measurement frame).
std::vector<Eigen::Vector3d> Pivots(const Robot& truth) {
  const Eigen::Isometry3d& B = truth.model().base();
  return {B * Eigen::Vector3d(0.7, 0.0, 0.3), B * Eigen::Vector3d(0.0, 0.7, 0.3), B * Eigen::Vector3d(-0.5, -0.5, 0.5)};
}

void MakeDistances(KindsCase* c, double noise = 0.0, uint64_t seed = 1) {
  const auto pivots = Pivots(c->truth);
  Rng rng(seed);
  for (size_t i = 0; i < c->data.rows.size(); ++i) {
    Measurement& m = c->data.rows[i];
    m.kind = MeasurementKind::kDistance;
    m.fixture = "P" + std::to_string(i % 3 + 1);
    m.distance = (m.p - pivots[i % 3]).norm() + noise * rng.Normal();
    m.p.setZero();
  }
}

// A plane n . p = offset: the measurement frame's z = 0.3 m above the truth base's origin.
void PlaneOf(const Robot& truth, Eigen::Vector3d* n, double* offset) {
  *n = Eigen::Vector3d::UnitZ();
  *offset = truth.model().base().translation().z() + 0.3;
}

// Noise (m, sd) along what each instrument reads, drawn from `seed`: the distance, the contact's height
// over its plane, the socket's position, a gauge's components.
void MakePlaneContacts(KindsCase* c, double noise = 0.0, uint64_t seed = 1) {
  Eigen::Vector3d n;
  double offset;
  PlaneOf(c->truth, &n, &offset);
  Rng rng(seed);
  std::vector<Measurement> kept;
  for (size_t i = 0; i < c->data.rows.size(); ++i) {
    const double e = noise * rng.Normal();
    const bool touched = Touch(*c, &c->data, i, [&](const Eigen::Vector3d& p) {
      return Eigen::VectorXd::Constant(1, n.dot(p) - offset - e);
    });
    Measurement m = c->data.rows[i];
    if (!touched || !WithinLimits(c->nominal, m.q)) continue;
    m.kind = MeasurementKind::kPlane;
    m.fixture = "table";
    m.p.setZero();
    kept.push_back(m);
  }
  c->data.rows = kept;
}

void MakeFixedPoints(KindsCase* c, double noise = 0.0, uint64_t seed = 1) {
  const Eigen::Vector3d socket = c->data.rows[0].p;  // a point the truth arm reaches
  const Eigen::VectorXd q0 = c->data.rows[0].q;
  Rng rng(13), noise_rng(seed);
  std::vector<Measurement> kept;
  for (size_t i = 0; i < c->data.rows.size(); ++i) {
    // The tool turned in the socket: the wrist moved, the first three joints solved.
    Eigen::VectorXd& q = c->data.rows[i].q;
    q = q0;
    for (int j = 3; j < q.size(); ++j) q[j] += rng.Uniform(-0.6, 0.6);
    const Eigen::Vector3d e(noise * noise_rng.Normal(), noise * noise_rng.Normal(), noise * noise_rng.Normal());
    const bool touched =
        Touch(*c, &c->data, i, [&](const Eigen::Vector3d& p) { return Eigen::VectorXd(p - socket - e); });
    Measurement m = c->data.rows[i];
    if (!touched || !WithinLimits(c->nominal, m.q)) continue;
    m.kind = MeasurementKind::kFixedPoint;
    m.fixture = "socket";
    m.p.setZero();
    kept.push_back(m);
  }
  c->data.rows = kept;
}

void MakePartialPoints(KindsCase* c, double noise = 0.0, uint64_t seed = 1) {
  Rng rng(seed);
  for (size_t i = 0; i < c->data.rows.size(); ++i) {
    Measurement& m = c->data.rows[i];
    for (int a = 0; a < 3; ++a) m.p[a] += noise * rng.Normal();
    if (i % 3 == 0) continue;
    m.axes = {{i % 3 == 1, true, i % 3 == 1}};
    for (int a = 0; a < 3; ++a) {
      if (!m.axes[a]) m.p[a] = 0.0;
    }
  }
}

Eigen::VectorXd StackedResiduals(const ErrorModelProblem& problem, const Eigen::VectorXd& x, Eigen::MatrixXd* J) {
  auto ws = problem.NewWorkspace();
  Eigen::VectorXd out(problem.num_residuals());
  if (J) J->resize(problem.num_residuals(), problem.num_parameters());
  int k = 0;
  Vector6d r;
  Matrix6Xd Jr;
  for (int i = 0; i < problem.num_rows(); ++i) {
    const int n = problem.EvaluateRow(i, x, ws.get(), &r, J ? &Jr : nullptr);
    out.segment(k, n) = r.head(n);
    if (J) J->middleRows(k, n) = Jr.topRows(n);
    k += n;
  }
  return out;
}

TEST(MeasurementKinds, JacobianOfEveryKindAndFixtureBlockMatchesCentralDifferences) {
  KindsCase c = RandomCase(40, 3);
  KindsCase d = c, pl = c, fp = c, pp = c;
  MakeDistances(&d);
  MakePlaneContacts(&pl);
  MakeFixedPoints(&fp);
  MakePartialPoints(&pp);
  Dataset mixed = pp.data;
  for (const Dataset* other : {&d.data, &pl.data, &fp.data}) {
    ASSERT_GE(other->rows.size(), 3u);
    const size_t take = std::min<size_t>(15, other->rows.size());  // a sphere fit needs four rows a pivot
    mixed.rows.insert(mixed.rows.end(), other->rows.begin(), other->rows.begin() + take);
  }
  const ErrorModelProblem problem(c.nominal, c.nominal, mixed, ErrorModelOptions());
  for (const char* block : {"pivot:P1", "pivot:P3", "plane:table", "point:socket", "geometry", "base"}) {
    const auto& blocks = problem.blocks();
    EXPECT_TRUE(std::any_of(blocks.begin(), blocks.end(), [&](const ParameterBlock& b) { return b.name == block; }))
        << block;
  }
  const Eigen::VectorXd x = problem.InitialX();
  Eigen::MatrixXd J;
  StackedResiduals(problem, x, &J);
  const Eigen::MatrixXd Jn =
      CentralDifference([&](const Eigen::VectorXd& y) { return StackedResiduals(problem, y, nullptr); }, x, 1e-6);
  const auto names = problem.ParameterNames();
  for (int j = 0; j < problem.num_parameters(); ++j) {
    const double scale = std::max(1.0, Jn.col(j).cwiseAbs().maxCoeff());
    EXPECT_LT((J.col(j) - Jn.col(j)).cwiseAbs().maxCoeff(), 2e-7 * scale) << names[j];
  }
}

std::vector<std::string> HeldNames(const PreparedErrorModel& prep) {
  std::vector<std::string> out;
  for (const auto& h : prep.problem->held()) out.push_back(h.parameter.name);
  return out;
}

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(MeasurementKinds, DistancesFromUnknownPivotsCannotSeeTheBase) {
  KindsCase c = RandomCase(150, 5);
  MakeDistances(&c);
  const PreparedErrorModel prep = PrepareErrorModel(c.nominal, c.nominal, c.data, ErrorModelOptions());
  const auto held = HeldNames(prep);
  for (const char* name : {"base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw"})
    EXPECT_TRUE(Contains(held, name)) << name;
  for (const char* name : {"pivot_P1_x", "pivot_P2_y", "pivot_P3_z"}) EXPECT_FALSE(Contains(held, name)) << name;
}

TEST(MeasurementKinds, OneKnownPlaneCannotSeeTheBasesInPlaneMovesAndTurn) {
  KindsCase c = RandomCase(150, 7);
  MakePlaneContacts(&c);
  ASSERT_GT(c.data.rows.size(), 60u);
  // The plane known and normal to the measurement frame's z: the base's x, y and yaw move along it and
  // change no contact at all.
  Robot start = c.nominal;
  start.model().SetBase(c.truth.model().base());
  Eigen::Vector3d n;
  double offset;
  PlaneOf(c.truth, &n, &offset);
  Fixture table;
  table.type = Fixture::Type::kPlane;
  table.name = "table";
  table.normal = n;
  table.offset = offset;
  table.known = true;
  start.fixtures.items.push_back(table);
  ErrorModelOptions options;
  options.initialize_bases = false;
  const PreparedErrorModel prep = PrepareErrorModel(start, c.nominal, c.data, options);
  const auto held = HeldNames(prep);
  for (const char* name : {"base_x", "base_y", "base_yaw"}) EXPECT_TRUE(Contains(held, name)) << name;
  for (const char* name : {"base_z", "base_roll", "base_pitch"}) EXPECT_FALSE(Contains(held, name)) << name;
}

TEST(MeasurementKinds, DistancesAloneRecoverTheArmsShape) {
  KindsCase c = RandomCase(150, 9);
  const KindsCase held_out = RandomCase(30, 10);
  MakeDistances(&c);
  YAML::Node options;
  options["parameter_tolerance"] = 1e-12;
  const auto estimator = Estimators().Create("least_squares", options);
  Robot identified;
  const EstimationReport report = estimator->Estimate(c.nominal, c.data, &identified);
  ASSERT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  // Distances between held-out points: the shape of the workspace, which no base can change.
  const auto truth = PredictMarkers(held_out.nominal, held_out.truth, held_out.data);
  const auto fitted = PredictMarkers(c.nominal, identified, held_out.data);
  const auto start = PredictMarkers(c.nominal, c.nominal, held_out.data);
  double worst = 0.0, worst_start = 0.0;
  for (size_t i = 1; i < truth.size(); ++i) {
    const double d = (truth[i] - truth[i - 1]).norm();
    worst = std::max(worst, std::abs((fitted[i] - fitted[i - 1]).norm() - d));
    worst_start = std::max(worst_start, std::abs((start[i] - start[i - 1]).norm() - d));
  }
  EXPECT_GT(worst_start, 1e-4);
  EXPECT_LT(worst, 1e-8);
}

// The four estimators minimise one cost over one parameter layout, so on every kind they end at one
// minimum: the same residual RMS and the same parameters (to a small fraction of their sd). Noisy rows,
// so that the minimum's RMS is a figure to agree on, not a rounding error of zero.
class KindsAgreement : public ::testing::TestWithParam<std::string> {};

TEST_P(KindsAgreement, TheFourEstimatorsReachOneMinimum) {
  const double noise = 10e-6;
  KindsCase c = RandomCase(150, 17);
  const std::string kind = GetParam();
  if (kind == "distance") MakeDistances(&c, noise, 41);
  if (kind == "plane") MakePlaneContacts(&c, noise, 42);
  if (kind == "fixed_point") MakeFixedPoints(&c, noise, 43);
  if (kind == "partial_point") MakePartialPoints(&c, noise, 44);
  ASSERT_GE(c.data.rows.size(), 25u);  // a socket is reached in fewer wrist turns than the others' rows
  std::map<std::string, EstimationReport> reports;
  for (const char* name : {"least_squares", "ceres", "nlopt", "ipopt"}) {
    Robot identified;
    EstimationReport& report = reports[name];
    report = Estimators().Create(name, YAML::Node())->Estimate(c.nominal, c.data, &identified);
    EXPECT_EQ(report.status, EstimationStatus::kConverged) << name << ": " << report.BriefReport();
    std::printf("%s, %s: %s\n", kind.c_str(), name, report.BriefReport().c_str());
  }
  const EstimationReport& ref = reports["least_squares"];
  EXPECT_GT(ref.final_rms, 0.3 * noise);
  for (const auto& [name, report] : reports) {
    EXPECT_NEAR(report.final_rms, ref.final_rms, 1e-6 * ref.final_rms) << name;
    ASSERT_EQ(report.parameters.size(), ref.parameters.size()) << name;
    for (size_t j = 0; j < ref.parameters.size(); ++j) {
      const ParameterEstimate& p = ref.parameters[j];
      if (!p.free) continue;
      EXPECT_NEAR(report.parameters[j].value, p.value, 1e-3 * p.stddev) << name << " " << p.name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryKind, KindsAgreement,
                         ::testing::Values("distance", "plane", "fixed_point", "partial_point"));

// The planes criterion: a simulated IRB 120 (examples/robots/irb120_as_measured.yaml the truth,
// irb120_placed.yaml the nominal arm standing where it does) touching three planes, 60 contacts each,
// 10 um scatter along the normals. Contacts fix no length (scale_hold.h): the planes given in the arm's
// frame (the robot file's fixtures, the base's place held) set the scale. Scored like the arms calibrated
// from distances: the distances between the points of 100 random configurations, identified arm against
// the truth, within 5 % of the nominal arm's error; a tracker's points at the same poses reach 1 %. With
// nothing given, or the three planes given but the base free (they meet in a point, about which the arm
// and base still scale: without a hold the fit shrinks the arm into the corner), the longest link is held
// at its nominal length.
TEST(MeasurementKinds, PlaneContactsWithGivenPlanesRecoverTheDistancesOfTheIrb120) {
  const Robot nominal = testing::LoadExampleRobot("irb120_placed.yaml");
  const Robot truth = testing::LoadExampleRobot("irb120_as_measured.yaml");
  SimulatorOptions o;
  o.protocol = "random";
  o.poses = 180;
  o.noise_sigma = 10e-6;
  o.instrument.instrument = "plane";
  o.instrument.fixtures = 3;
  o.seed = 3;
  const Dataset planes = Simulate(nominal, truth, o);
  ASSERT_EQ(planes.rows.size(), 180u);
  SimulatorOptions random;
  random.protocol = "random";
  random.poses = 100;
  random.seed = 99;
  const Dataset configurations = Simulate(nominal, truth, random);
  Dataset tracker = planes;
  const std::vector<Eigen::Vector3d> p = PredictMarkers(nominal, truth, planes);
  Rng rng(7);
  for (size_t i = 0; i < tracker.rows.size(); ++i) {
    Measurement& m = tracker.rows[i];
    m.kind = MeasurementKind::kPoint;
    m.fixture.clear();
    m.p = p[i] + 10e-6 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
  }
  Robot given = nominal;
  given.fixtures.items = InstrumentFixtures(nominal, truth, o.instrument, "", o.seed);
  for (Fixture& f : given.fixtures.items) f.known = true;
  const double before = PairwiseDistanceErrors(nominal, nominal, configurations).rms;
  const auto ratio = [&](const Robot& start, const Dataset& data, const char* options) {
    Robot identified;
    const EstimationReport report =
        Estimators().Create("least_squares", YAML::Load(options))->Estimate(start, data, &identified);
    EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
    return PairwiseDistanceErrors(nominal, identified, configurations).rms / before;
  };
  const double tracker_ratio = ratio(nominal, tracker, "{}");
  const double planes_ratio = ratio(given, planes, "{fixed: [base], initialize_bases: false}");
  const double held_ratio = ratio(nominal, planes, "{}");
  std::printf("distances between random points, RMS error over the nominal arm's (%.4f mm): tracker %.4f, given "
              "planes %.4f, unknown planes (longest link held) %.4f\n",
              before * 1e3, tracker_ratio, planes_ratio, held_ratio);
  EXPECT_LE(tracker_ratio, 0.01);
  EXPECT_LE(planes_ratio, 0.05);
  ErrorModelOptions free_base, held_base;
  held_base.fixed = {"base"};
  held_base.initialize_bases = false;
  EXPECT_TRUE(Contains(HeldNames(PrepareErrorModel(nominal, nominal, planes, free_base)), "d_4"));  // 302 mm
  EXPECT_TRUE(Contains(HeldNames(PrepareErrorModel(given, nominal, planes, free_base)), "d_4"));
  EXPECT_FALSE(Contains(HeldNames(PrepareErrorModel(given, nominal, planes, held_base)), "d_4"));
}

// One given plane with the base held reads one length: the distance from the base to the plane along its
// normal. The arm takes over a held base's moves along joint 1's axis (d_1 translates everything along it),
// so only a plane whose normal is square to that axis (a wall beside a standing arm) sets the scale; a
// table under it or a tilted plane does not: the arm scaled about the point where joint 1's axis meets the
// plane, d_1 taking up the difference, touches it as before, and without a hold shrinks to nothing. The
// simulated IRB 120 (180 mm from the wall, its d_4 0.28 mm longer than the nominal's): the wall gives d_4
// and a_3 to a few um; the others hold d_4 and keep the arm's size.
TEST(MeasurementKinds, OneGivenPlaneWithTheBaseHeldSetsTheScaleOnlySquareToJointOnesAxis) {
  const Robot nominal = testing::LoadExampleRobot("irb120_placed.yaml");
  const Robot truth_arm = testing::LoadExampleRobot("irb120_as_measured.yaml");
  const auto length = [](const Robot& r, const std::string& name) {
    const auto names = r.model().ParameterNames();
    return r.model().Parameters()[std::find(names.begin(), names.end(), name) - names.begin()];
  };
  struct Case {
    const char* name;
    Eigen::Vector3d normal;
    double offset;  // m
    bool sets_scale;
  };
  for (const Case& c : {Case{"wall", -Eigen::Vector3d::UnitX(), -1.16, true},
                        Case{"table", Eigen::Vector3d::UnitZ(), -0.1, false},
                        Case{"tilted", Eigen::Vector3d(0.6, 0.0, 0.8), 0.82, false}}) {
    SCOPED_TRACE(c.name);
    Fixture plane;
    plane.type = Fixture::Type::kPlane;
    plane.name = c.name;
    plane.normal = c.normal;
    plane.offset = c.offset;
    plane.known = true;
    Robot truth = truth_arm, start = nominal;
    truth.fixtures.items = start.fixtures.items = {plane};
    SimulatorOptions o;
    o.protocol = "random";
    o.poses = 80;
    o.noise_sigma = 2e-6;
    o.instrument.instrument = "plane";
    o.seed = 5;
    const Dataset data = Simulate(nominal, truth, o);
    ASSERT_EQ(data.rows.size(), 80u);
    ErrorModelOptions held_base;
    held_base.fixed = {"base"};
    held_base.initialize_bases = false;
    EXPECT_EQ(Contains(HeldNames(PrepareErrorModel(start, nominal, data, held_base)), "d_4"), !c.sets_scale);
    Robot identified;
    const EstimationReport report =
        Estimators()
            .Create("least_squares", YAML::Load("{fixed: [base], initialize_bases: false}"))
            ->Estimate(start, data, &identified);
    EXPECT_GT(report.final_rms, 0.0);
    EXPECT_LT(report.final_rms, 5e-6) << report.BriefReport();
    for (const char* name : {"d_1", "a_3", "d_4"}) {
      EXPECT_NEAR(length(identified, name), length(truth, name), c.sets_scale ? 2e-5 : 1e-3) << name;
    }
  }
}

TEST(MeasurementKinds, FixtureRowsOutsideSessionZeroAreRefused) {
  KindsCase c = RandomCase(40, 11);
  MakeDistances(&c);
  c.data.rows[3].session = 2;
  EXPECT_THROW(ErrorModelProblem(c.nominal, c.nominal, c.data, ErrorModelOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
