// One conformance suite that every model passes (manif MANIF_TEST_JACOBIANS, Sophus LieGroupTests):
// every analytic derivative against central differences, frame consistency, parameter bookkeeping.
#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/poe_model.h"
#include "models/mdh_model.h"
#include "models/model_factory.h"
#include "models/urdf_model.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::CentralDifference;
using testing::RandomizedModel;

struct ModelCase {
  std::string label;
  std::function<std::unique_ptr<KinematicModel>()> make;
};
void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.label; }

class ModelConformance : public ::testing::TestWithParam<ModelCase> {
 protected:
  Eigen::VectorXd RandomJoints(const KinematicModel& m, uint64_t seed) {
    Rng rng(seed);
    Eigen::VectorXd q(m.dof());
    for (int i = 0; i < m.dof(); ++i) q[i] = rng.Uniform(-3.0, 3.0);
    return q;
  }
};

// Position of a tool point and a rotation-vector parametrisation of the orientation around R0, so that
// the finite difference of the orientation is an angular velocity comparable to rows 3-5.
Eigen::VectorXd PoseVector(const Eigen::Isometry3d& T, const Eigen::Matrix3d& R0, const Eigen::Vector3d& point) {
  Eigen::VectorXd v(6);
  v.head<3>() = T * point;
  v.tail<3>() = RotationLog(T.linear() * R0.transpose());
  return v;
}

TEST_P(ModelConformance, JointJacobianMatchesCentralDifferences) {
  const auto model = GetParam().make();
  const Eigen::Vector3d point(0.03, -0.02, 0.05);
  for (uint64_t trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomJoints(*model, 100 + trial);
    const Eigen::Matrix3d R0 = model->ForwardKinematics(q).linear();
    const auto f = [&](const Eigen::VectorXd& x) { return PoseVector(model->ForwardKinematics(x), R0, point); };
    const Eigen::MatrixXd numeric = CentralDifference(f, q);
    const Eigen::MatrixXd analytic = model->JointJacobian(q, point);
    EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
  }
}

TEST_P(ModelConformance, ParameterJacobianMatchesCentralDifferences) {
  auto model = GetParam().make();
  const Eigen::Vector3d point(-0.01, 0.04, 0.02);
  for (uint64_t trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomJoints(*model, 200 + trial);
    const Eigen::VectorXd p0 = model->Parameters();
    const Eigen::Matrix3d R0 = model->ForwardKinematics(q).linear();
    auto probe = model->Clone();
    const auto f = [&](const Eigen::VectorXd& p) {
      probe->SetParameters(p);
      return PoseVector(probe->ForwardKinematics(q), R0, point);
    };
    const Eigen::MatrixXd numeric = CentralDifference(f, p0);
    Matrix6Xd analytic;
    const Eigen::Isometry3d T = model->ParameterJacobian(q, point, &analytic);
    EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    EXPECT_TRUE(T.isApprox(model->ForwardKinematics(q), 1e-14));
  }
}

TEST_P(ModelConformance, PoseDerivativesMatchCentralDifferences) {
  const auto model = GetParam().make();
  const Eigen::VectorXd q = RandomJoints(*model, 300);
  const std::vector<Eigen::Matrix4d> dT = model->PoseDerivatives(q);
  ASSERT_EQ(static_cast<int>(dT.size()), model->dof());
  for (int i = 0; i < model->dof(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    const double h = 1e-6;
    qp[i] += h;
    qm[i] -= h;
    const Eigen::Matrix4d numeric =
        (model->ForwardKinematics(qp).matrix() - model->ForwardKinematics(qm).matrix()) / (2 * h);
    EXPECT_LT((numeric - dT[i]).cwiseAbs().maxCoeff(), 1e-8) << "joint " << i + 1;
    EXPECT_EQ(dT[i].row(3), Eigen::RowVector4d::Zero());
  }
}

TEST_P(ModelConformance, FramePosesEndAtForwardKinematics) {
  const auto model = GetParam().make();
  const Eigen::VectorXd q = RandomJoints(*model, 400);
  const auto frames = model->FramePoses(q);
  ASSERT_EQ(static_cast<int>(frames.size()), model->dof() + 2);
  EXPECT_TRUE(frames.back().isApprox(model->ForwardKinematics(q), 1e-13));
  EXPECT_TRUE(frames.front().isApprox(model->base(), 1e-13));
  for (const auto& T : frames)
    EXPECT_NEAR((T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-13);
}

TEST_P(ModelConformance, JointAxesAreFrameZAxes) {
  // Joint i turns about z of the frame the model names (JointAxisFrame: frame i for MDH, i-1 for DH).
  const auto model = GetParam().make();
  const Eigen::VectorXd q = RandomJoints(*model, 500);
  const auto frames = model->FramePoses(q);
  const Matrix6Xd J = model->JointJacobian(q);
  for (int i = 0; i < model->dof(); ++i) {
    Eigen::Vector3d z;
    if (const auto* urdf = dynamic_cast<const UrdfModel*>(model.get())) {
      z = frames[i + 1].linear() * urdf->JointAxis(i);  // URDF: any direction in the child link's frame
    } else {
      ASSERT_GE(model->JointAxisFrame(i), 0) << "a model of this suite names each joint's axis frame";
      z = frames[model->JointAxisFrame(i)].linear().col(2);
    }
    // A revolute joint turns about z; a prismatic one slides along it.
    const Eigen::Vector3d axis = model->joint_type(i) == JointType::kRevolute ? J.col(i).tail<3>() : J.col(i).head<3>();
    EXPECT_TRUE(axis.isApprox(z, 1e-12)) << "joint " << i + 1;
  }
}

TEST_P(ModelConformance, BaseAndToolRoundTrip) {
  auto model = GetParam().make();
  const Eigen::Isometry3d base = PoseFromXyzRpy({0.1, -0.2, 0.3}, {0.3, -0.4, 1.2});
  const Eigen::Isometry3d tool = PoseFromXyzRpy({0.01, 0.02, 0.03}, {-0.1, 0.2, -0.3});
  const Eigen::VectorXd q = RandomJoints(*model, 600);
  const Eigen::Isometry3d before = model->base().inverse() * model->ForwardKinematics(q) * model->tool().inverse();
  model->SetBase(base);
  model->SetTool(tool);
  EXPECT_TRUE(model->base().isApprox(base, 1e-14));
  EXPECT_TRUE(model->tool().isApprox(tool, 1e-14));
  EXPECT_TRUE(model->ForwardKinematics(q).isApprox(base * before * tool, 1e-12));
}

TEST_P(ModelConformance, ParametersByName) {
  auto model = GetParam().make();
  const auto names = model->ParameterNames();
  EXPECT_EQ(static_cast<int>(names.size()), static_cast<int>(model->RowKeys().size()) * model->dof() + 12);
  const std::string name = names[5];
  model->SetParameter(name, 0.25);
  EXPECT_EQ(model->Parameter(name), 0.25);
  EXPECT_THROW(model->ParameterIndex("a_99"), std::invalid_argument);
  const std::string joint_name = model->FindParameter("theta_1") >= 0 ? "theta_1" : names[0];
  model->SetFree(joint_name, false);
  EXPECT_FALSE(model->FreeMask()[model->ParameterIndex(joint_name)]);
  const auto clone = model->Clone();
  EXPECT_EQ(clone->Parameters(), model->Parameters());
  EXPECT_EQ(clone->FreeMask(), model->FreeMask());
}

// Converting any model to local POE keeps its forward kinematics for every q.
TEST(PoeConversion, SameForwardKinematicsAsTheSourceModel) {
  for (uint64_t seed = 11; seed < 14; ++seed) {
    const auto mdh = RandomizedModel(std::make_unique<MdhModel>(6), seed);
    const auto dh = RandomizedModel(std::make_unique<DhModel>(6), seed + 10);
    const auto rpr = RandomizedModel(std::make_unique<MdhModel>(std::vector<JointType>{
                                    JointType::kRevolute, JointType::kPrismatic, JointType::kRevolute}),
                                seed + 20);
    for (const KinematicModel* source : {mdh.get(), dh.get(), rpr.get()}) {
      const PoeModel poe = PoeModel::FromModel(*source);
      Rng rng(seed);
      for (int k = 0; k < 10; ++k) {
        Eigen::VectorXd q(source->dof());
        for (int i = 0; i < source->dof(); ++i) q[i] = rng.Uniform(-3, 3);
        EXPECT_TRUE(poe.ForwardKinematics(q).isApprox(source->ForwardKinematics(q), 1e-12)) << source->convention();
      }
    }
  }
}

// Every registered convention (a plugin's too, registered before the tests start) with six revolute
// joints and with a prismatic joint between two revolute ones; then other sizes and joint mixes.
std::vector<ModelCase> ModelCases() {
  using J = JointType;
  const std::vector<std::pair<std::string, std::vector<JointType>>> shapes = {
      {"6", std::vector<JointType>(6, J::kRevolute)}, {"_rpr", {J::kRevolute, J::kPrismatic, J::kRevolute}}};
  std::vector<ModelCase> cases;
  uint64_t seed = 1;
  for (const std::string& convention : ModelConventions()) {
    for (const auto& [suffix, joints] : shapes) {
      cases.push_back({convention + suffix, [convention, joints = joints, s = seed++] {
                         return RandomizedModel(MakeModel(convention, joints), s);
                       }});
    }
  }
  cases.push_back({"mdh3", [] { return RandomizedModel(std::make_unique<MdhModel>(3), 3); }});
  cases.push_back({"mdh7", [] { return RandomizedModel(std::make_unique<MdhModel>(7), 4); }});
  cases.push_back({"mdh_rrp", [] {
                     return RandomizedModel(std::make_unique<MdhModel>(std::vector<JointType>{
                                                JointType::kRevolute, JointType::kRevolute, JointType::kPrismatic}),
                                            5);
                   }});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(
    AllModels, ModelConformance, ::testing::ValuesIn(ModelCases()),
    [](const ::testing::TestParamInfo<ModelCase>& info) { return info.param.label; });

}  // namespace
}  // namespace kincal
