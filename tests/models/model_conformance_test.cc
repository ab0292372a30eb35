// One conformance suite that every model passes (manif MANIF_TEST_JACOBIANS, Sophus LieGroupTests): the
// installed kit's checks (testing/model_conformance.h) and what the kit cannot know of the built-in models.
#include <gtest/gtest.h>

#include "framework/random.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/poe_model.h"
#include "models/mdh_model.h"
#include "models/model_factory.h"
#include "models/urdf_model.h"
#include "testing/model_conformance.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RandomizedModel;
using testing::RandomJoints;

struct ModelCase {
  std::string label;
  std::function<std::unique_ptr<KinematicModel>()> make;
};
void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.label; }

class ModelConformance : public ::testing::TestWithParam<ModelCase> {};

// The checks of the installed kit (testing/model_conformance.h): joint, parameter and pose derivatives
// against central differences, frames, base and tool, parameter round trips.
TEST_P(ModelConformance, PassesTheConformanceKit) {
  testing::ExpectModelConforms(*GetParam().make(), 100, 5);
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

// One row of parameters per joint (RowKeys) plus the base's and the tool's six each.
TEST_P(ModelConformance, ParametersAreRowsPerJointPlusBaseAndTool) {
  const auto model = GetParam().make();
  EXPECT_EQ(static_cast<int>(model->ParameterNames().size()),
            static_cast<int>(model->RowKeys().size()) * model->dof() + 12);
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
