// kincal's forward kinematics and joint Jacobian against orocos KDL (ChainFkSolverPos_recursive,
// ChainJntToJacSolver) on the same chains, at random geometry and configurations; and the IRB 120 example
// file against ROS-Industrial's URDF of the arm, rebuilt joint by joint in KDL.
#include <gtest/gtest.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "framework/random.h"
#include "models/dh_model.h"
#include "models/mdh_model.h"
#include "tests/support/kdl_reference.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::FromKdl;
using testing::KdlChain;
using testing::ToKdl;

void Randomize(KinematicModel* model, uint64_t seed) {
  Rng rng(seed);
  Eigen::VectorXd p = model->Parameters();
  for (int i = 0; i < p.size(); ++i) {
    const bool angle = model->parameter_info()[i].kind == ParameterInfo::Kind::kAngle;
    p[i] = angle ? rng.Uniform(-M_PI, M_PI) : rng.Uniform(-0.8, 0.8);
  }
  model->SetParameters(p);
}

// Compares pose and Jacobian with KDL at random configurations; lengths of the model are below ~5 m.
void ExpectAgreesWithKdl(const KinematicModel& model, uint64_t seed, int trials = 50) {
  const KDL::Chain chain = KdlChain(model);
  ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), model.dof());
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  Rng rng(seed);
  for (int t = 0; t < trials; ++t) {
    Eigen::VectorXd q(model.dof());
    for (int j = 0; j < model.dof(); ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    KDL::Frame f;
    KDL::Jacobian J(model.dof());
    ASSERT_GE(fk.JntToCart(ToKdl(q), f), 0);
    ASSERT_GE(jac.JntToJac(ToKdl(q), J), 0);
    const Eigen::Isometry3d T = model.ForwardKinematics(q);
    EXPECT_LT((T.matrix() - FromKdl(f).matrix()).cwiseAbs().maxCoeff(), 1e-14) << "trial " << t;
    EXPECT_LT((model.JointJacobian(q) - FromKdl(J)).cwiseAbs().maxCoeff(), 1e-14) << "trial " << t;
  }
}

TEST(KdlReference, ModifiedDhWithRandomGeometry) {
  for (int dof : {1, 3, 6, 7}) {
    MdhModel model(dof);
    Randomize(&model, 10 + dof);
    SCOPED_TRACE(dof);
    ExpectAgreesWithKdl(model, 100 + dof);
  }
}

TEST(KdlReference, StandardDhWithRandomGeometry) {
  for (int dof : {1, 3, 6, 7}) {
    DhModel model(dof);
    Randomize(&model, 20 + dof);
    SCOPED_TRACE(dof);
    ExpectAgreesWithKdl(model, 200 + dof);
  }
}

TEST(KdlReference, PrismaticJoints) {
  using J = JointType;
  MdhModel mdh({J::kRevolute, J::kPrismatic, J::kRevolute, J::kPrismatic});
  DhModel dh({J::kPrismatic, J::kRevolute, J::kRevolute, J::kPrismatic});
  Randomize(&mdh, 31);
  Randomize(&dh, 32);
  ExpectAgreesWithKdl(mdh, 301);
  ExpectAgreesWithKdl(dh, 302);
}

TEST(KdlReference, EveryExampleRobot) {
  for (const char* file : {"seed_nominal.yaml", "seed_identified.yaml", "puma560_dh.yaml", "puma560_mdh.yaml",
                           "ur10_dh.yaml", "irb120_mdh.yaml"}) {
    SCOPED_TRACE(file);
    ExpectAgreesWithKdl(testing::LoadExampleRobot(file).model(), 400);
  }
}

// ROS-Industrial abb_irb120_support/urdf/irb120_3_58_macro.xacro: each joint an origin (xyz, no
// rotation) and an axis; tool0 is the flange turned +90 deg about y. Written here as a KDL chain.
KDL::Chain RosIndustrialIrb120() {
  struct UrdfJoint {
    double x, y, z;
    KDL::Joint::JointType axis;
  };
  const UrdfJoint joints[6] = {{0, 0, 0, KDL::Joint::RotZ},     {0, 0, 0.29, KDL::Joint::RotY},
                               {0, 0, 0.27, KDL::Joint::RotY},  {0, 0, 0.07, KDL::Joint::RotX},
                               {0.302, 0, 0, KDL::Joint::RotY}, {0.072, 0, 0, KDL::Joint::RotX}};
  KDL::Chain chain;
  for (const UrdfJoint& j : joints) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(KDL::Vector(j.x, j.y, j.z))));
    chain.addSegment(KDL::Segment(KDL::Joint(j.axis)));
  }
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(KDL::Rotation::RPY(0, M_PI / 2, 0))));
  return chain;
}

TEST(KdlReference, Irb120ExampleFileIsRosIndustrialsUrdf) {
  const Robot robot = testing::LoadExampleRobot("irb120_mdh.yaml");
  const KDL::Chain urdf = RosIndustrialIrb120();
  KDL::ChainFkSolverPos_recursive fk(urdf);
  Rng rng(5);
  for (int t = 0; t < 100; ++t) {
    Eigen::VectorXd q(6);
    for (int j = 0; j < 6; ++j) {
      const auto [low, high] = robot.Limit(j);
      q[j] = rng.Uniform(low, high);
    }
    KDL::Frame f;
    ASSERT_GE(fk.JntToCart(ToKdl(q), f), 0);
    EXPECT_LT((robot.model().ForwardKinematics(q).matrix() - FromKdl(f).matrix()).cwiseAbs().maxCoeff(), 1e-14)
        << "q = " << q.transpose();
  }
}

}  // namespace
}  // namespace kincal
