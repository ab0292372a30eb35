// Forward kinematics, and forward kinematics + joint Jacobian, for the seed's arm
// (examples/robots/seed_nominal.yaml: modified DH, marker 40/30/100 mm off the flange): kincal against
// orocos KDL (ChainFkSolverPos_recursive, ChainJntToJacSolver) on the same chain, built from the same MDH
// table with Frame::DH_Craig1989 and the tool as the last segment's tip. Target: kincal at most half of
// KDL's time per call.
//
//   ./build/bench/kincal_kinematics_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <vector>

#include <benchmark/benchmark.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "framework/random.h"
#include "robot/robot_file.h"
#include "tests/support/kdl_reference.h"

namespace kincal {
namespace {

const Robot& Seed() {
  static const Robot robot = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/seed_nominal.yaml");
  return robot;
}

// A fixed set of configurations within the limits, cycled through so that no call sees a constant input.
const std::vector<Eigen::VectorXd>& Configurations() {
  static const std::vector<Eigen::VectorXd> qs = [] {
    std::vector<Eigen::VectorXd> out;
    Rng rng(1);
    for (int k = 0; k < 1024; ++k) {
      Eigen::VectorXd q(Seed().dof());
      for (int j = 0; j < q.size(); ++j) q[j] = rng.Uniform(Seed().Limit(j).first, Seed().Limit(j).second);
      out.push_back(q);
    }
    return out;
  }();
  return qs;
}

std::vector<KDL::JntArray> KdlConfigurations() {
  std::vector<KDL::JntArray> out;
  for (const auto& q : Configurations()) out.push_back(testing::ToKdl(q));
  return out;
}

void BM_Fk_Kincal(benchmark::State& state) {
  const KinematicModel& model = Seed().model();
  const auto& qs = Configurations();
  size_t k = 0;
  for (auto _ : state) {
    Eigen::Isometry3d T = model.ForwardKinematics(qs[k++ & 1023]);
    benchmark::DoNotOptimize(T);
  }
}
BENCHMARK(BM_Fk_Kincal);

void BM_Fk_Kdl(benchmark::State& state) {
  const KDL::Chain chain = testing::KdlChain(Seed().model());
  KDL::ChainFkSolverPos_recursive fk(chain);
  const auto qs = KdlConfigurations();
  KDL::Frame f;
  size_t k = 0;
  for (auto _ : state) {
    fk.JntToCart(qs[k++ & 1023], f);
    benchmark::DoNotOptimize(f);
  }
}
BENCHMARK(BM_Fk_Kdl);

void BM_FkJacobian_Kincal(benchmark::State& state) {
  const KinematicModel& model = Seed().model();
  const auto& qs = Configurations();
  size_t k = 0;
  for (auto _ : state) {
    const Eigen::VectorXd& q = qs[k++ & 1023];
    Eigen::Isometry3d T = model.ForwardKinematics(q);
    Matrix6Xd J = model.JointJacobian(q);
    benchmark::DoNotOptimize(T);
    benchmark::DoNotOptimize(J.data());
  }
}
BENCHMARK(BM_FkJacobian_Kincal);

void BM_FkJacobian_Kdl(benchmark::State& state) {
  const KDL::Chain chain = testing::KdlChain(Seed().model());
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  const auto qs = KdlConfigurations();
  KDL::Frame f;
  KDL::Jacobian J(chain.getNrOfJoints());
  size_t k = 0;
  for (auto _ : state) {
    const KDL::JntArray& q = qs[k++ & 1023];
    fk.JntToCart(q, f);
    jac.JntToJac(q, J);
    benchmark::DoNotOptimize(f);
    benchmark::DoNotOptimize(J.data.data());
  }
}
BENCHMARK(BM_FkJacobian_Kdl);

}  // namespace
}  // namespace kincal

BENCHMARK_MAIN();
