// Measurement factors (estimators/error_model/factor.h): every registered kind's analytic Jacobian, with
// respect to the pose and to its fixture block, against central differences; the pose predictor's
// Jacobian against central differences of the predicted position and orientation.
#include <array>

#include <gtest/gtest.h>

#include "estimators/error_model/error_model.h"
#include "estimators/error_model/factor.h"
#include "framework/random.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::CentralDifference;

// A row of each kind near a pose p0, R0, with a fixture block f0 that the row nearly satisfies.
struct FactorSample {
  Measurement m;
  FixtureValue fixture;
};

std::vector<FactorSample> Samples(const std::string& kind, const Eigen::Vector3d& p0, const Eigen::Matrix3d& R0,
                                  Rng* rng) {
  std::vector<FactorSample> out;
  if (kind == "point") {
    FactorSample s;
    s.m.p = p0 + Eigen::Vector3d(rng->Uniform(-1e-3, 1e-3), rng->Uniform(-1e-3, 1e-3), rng->Uniform(-1e-3, 1e-3));
    out.push_back(s);
    for (const std::array<bool, 3> axes : {std::array<bool, 3>{{true, false, true}}, {{false, false, true}}}) {
      FactorSample partial = s;
      partial.m.axes = axes;
      out.push_back(partial);
    }
    s.m.orientation = Eigen::Quaterniond(RotationExp(Eigen::Vector3d(0.01, -0.02, 0.015)) * R0);
    out.push_back(s);
  } else if (kind == "distance" || kind == "fixed_point") {
    FactorSample s;
    s.fixture.x = p0 + Eigen::Vector3d(0.4, -0.3, 0.2);
    s.m.distance = (p0 - s.fixture.x).norm() + rng->Uniform(-1e-3, 1e-3);
    out.push_back(s);
  } else if (kind == "plane") {
    FactorSample s;
    s.fixture.reference = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
    s.fixture.x = Eigen::Vector3d(0.05, -0.03, s.fixture.reference.dot(p0) + 1e-3);
    out.push_back(s);
  }
  return out;
}

// x = (dp, dtheta, f): p = p0 + dp, R = Exp(dtheta) R0, so that the pose Jacobian is [I 0].
Eigen::VectorXd Residual(const MeasurementFactor& factor, const FactorSample& s, const Eigen::Vector3d& p0,
                         const Eigen::Matrix3d& R0, const Eigen::VectorXd& x) {
  PredictedPose pose;
  pose.p = p0 + x.head<3>();
  pose.R = RotationExp(x.segment<3>(3)) * R0;
  Vector6d r;
  FixtureValue fixture = s.fixture;
  if (x.size() > 6) fixture.x = x.tail<3>();
  const int k = factor.Evaluate(s.m, FactorContext(), pose, x.size() > 6 ? &fixture : nullptr, &r, nullptr, nullptr);
  return r.head(k);
}

TEST(MeasurementFactor, EveryKindsJacobianMatchesCentralDifferences) {
  Rng rng(11);
  int kinds = 0;
  for (const auto& entry : MeasurementFactors()) {
    const MeasurementFactor& factor = *entry.second;
    EXPECT_EQ(entry.first, factor.kind());
    const Eigen::Vector3d p0(0.6, -0.2, 0.4);
    const Eigen::Matrix3d R0 = RotationExp(Eigen::Vector3d(0.3, -0.5, 1.1));
    const std::vector<FactorSample> samples = Samples(entry.first, p0, R0, &rng);
    EXPECT_FALSE(samples.empty()) << entry.first << ": no sample rows in this test";
    for (const FactorSample& s : samples) {
      const int nf = factor.FixtureSize();
      Eigen::VectorXd x = Eigen::VectorXd::Zero(6 + nf);
      if (nf > 0) x.tail(nf) = s.fixture.x.head(nf);
      PredictedPose pose;
      pose.p = p0;
      pose.R = R0;
      Vector6d r;
      Matrix6Xd J = Matrix6Xd::Zero(6, 6);
      J.setIdentity();
      Matrix6x3d Jf = Matrix6x3d::Zero();
      const int k = factor.Evaluate(s.m, FactorContext(), pose, nf > 0 ? &s.fixture : nullptr, &r, &J, &Jf);
      ASSERT_EQ(k, factor.Dimension(s.m));
      const Eigen::MatrixXd Jn =
          CentralDifference([&](const Eigen::VectorXd& y) { return Residual(factor, s, p0, R0, y); }, x, 1e-7);
      EXPECT_LT((J.topRows(k) - Jn.leftCols(6)).cwiseAbs().maxCoeff(), 1e-7) << entry.first;
      if (nf > 0) {
        EXPECT_LT((Jf.topLeftCorner(k, nf) - Jn.rightCols(nf)).cwiseAbs().maxCoeff(), 1e-7) << entry.first;
      }
    }
    ++kinds;
  }
  EXPECT_GE(kinds, 1);
}

TEST(MeasurementFactor, UnknownKindIsRefusedNamingTheRegisteredOnes) {
  try {
    FactorOfKind("ballbar");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point"), std::string::npos) << e.what();
  }
}

// The pose predictor: position and orientation derivatives of every free parameter of the seed's arm
// with ratios, a marker and two sessions.
TEST(PosePredictor, PoseJacobianMatchesCentralDifferences) {
  Robot start = testing::SeedNominal();
  start.markers["A"] = Eigen::Vector3d(0.04, 0.03, 0.10);
  Robot truth = start;
  truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(1.5, -0.4, 0.2), Eigen::Vector3d(0.1, -0.2, 1.4)));
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = 30;
  so.seed = 5;
  Dataset data = Simulate(start, truth, so);
  for (size_t i = 0; i < data.rows.size(); ++i) {
    data.rows[i].marker = "A";
    data.rows[i].session = static_cast<int>(i % 2);
  }
  const ErrorModelProblem problem(start, start, data, ErrorModelOptions());
  const Eigen::VectorXd x0 = problem.InitialX();
  auto ws = problem.NewWorkspace();
  for (int row : {0, 1, 7}) {
    PredictedPose pose0;
    Matrix6Xd J;
    problem.PredictRowPose(row, x0, ws.get(), &pose0, &J);
    // Position, and the rotation relative to R(x0) as a rotation vector: its derivative is the angular velocity.
    const auto f = [&](const Eigen::VectorXd& x) {
      PredictedPose pose;
      problem.PredictRowPose(row, x, ws.get(), &pose, nullptr);
      Eigen::VectorXd out(6);
      out << pose.p, RotationLog(pose.R * pose0.R.transpose());
      return out;
    };
    const Eigen::MatrixXd Jn = CentralDifference(f, x0, 1e-6);
    const auto names = problem.ParameterNames();
    for (int j = 0; j < problem.num_parameters(); ++j) {
      const double scale = std::max(1.0, Jn.col(j).cwiseAbs().maxCoeff());
      EXPECT_LT((J.col(j) - Jn.col(j)).cwiseAbs().maxCoeff(), 2e-7 * scale) << names[j] << " row " << row;
    }
  }
}

}  // namespace
}  // namespace kincal
