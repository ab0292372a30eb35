// Inverse kinematics of the four example arms (framework/nominal_ik.h) beside orocos KDL's
// ChainIkSolverPos_LMA, plain (one start, the middle of the limits) and with random restarts within the
// limits until it solves the target or gives up after 20 starts; and seedless compensation on the
// command line against the same targets with seeds (issue 12).
//
// Targets: 1000 poses of random configurations within the joint limits (seed 12), no seeds: each solver
// starts from the middle of the limits. Solved: pose error <= 1e-9 m and 1e-9 rad with every joint inside
// its limits (after 2 pi wraps). Counters: solve_rate, mean_us and worst_us per target (steady clock).
//
//   ./build/bench/kincal_ik_bench --benchmark_counters_tabular=true
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <benchmark/benchmark.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include "framework/math.h"
#include "framework/nominal_ik.h"
#include "framework/random.h"
#include "framework/robot_file.h"
#include "tests/support/kdl_reference.h"

namespace kincal {
namespace {

constexpr int kTargets = 1000;

struct Arm {
  Robot robot;
  std::vector<Eigen::VectorXd> q;
  std::vector<Eigen::Isometry3d> T;
};

const Arm& GetArm(const std::string& file) {
  static std::map<std::string, Arm> arms;
  auto it = arms.find(file);
  if (it != arms.end()) return it->second;
  Arm arm;
  arm.robot = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/" + file);
  Rng rng(12);
  for (int k = 0; k < kTargets; ++k) {
    Eigen::VectorXd q(arm.robot.dof());
    for (int j = 0; j < q.size(); ++j) q[j] = rng.Uniform(arm.robot.Limit(j).first, arm.robot.Limit(j).second);
    arm.q.push_back(q);
    arm.T.push_back(arm.robot.model().ForwardKinematics(q));
  }
  return arms.emplace(file, std::move(arm)).first->second;
}

// Reached within the limits (revolute joints moved by 2 pi where that brings them inside).
bool Solved(const Robot& robot, const Eigen::Isometry3d& T, Eigen::VectorXd q) {
  const Vector6d e = PoseError(robot.model().ForwardKinematics(q), T);
  if (!(e.head<3>().norm() <= 1e-9 && e.tail<3>().norm() <= 1e-9)) return false;
  for (int j = 0; j < q.size(); ++j) {
    const auto [low, high] = robot.Limit(j);
    bool inside = false;
    for (int k = -2; k <= 2; ++k) inside = inside || (q[j] + 2 * M_PI * k >= low - 1e-12 && q[j] + 2 * M_PI * k <= high + 1e-12);
    if (!inside) return false;
  }
  return true;
}

template <typename SolveFn>
void Measure(benchmark::State& state, const Arm& arm, SolveFn solve) {
  using Clock = std::chrono::steady_clock;
  int solved = 0;
  double total = 0.0, worst = 0.0;
  for (auto _ : state) {
    solved = 0;
    total = worst = 0.0;
    for (int k = 0; k < kTargets; ++k) {
      const auto t0 = Clock::now();
      const Eigen::VectorXd q = solve(k);
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      total += s;
      worst = std::max(worst, s);
      solved += Solved(arm.robot, arm.T[k], q);
    }
  }
  state.counters["solve_rate"] = double(solved) / kTargets;
  state.counters["mean_us"] = total / kTargets * 1e6;
  state.counters["worst_us"] = worst * 1e6;
}

void BM_Ik_Kincal(benchmark::State& state, const std::string& file) {
  const Arm& arm = GetArm(file);
  const NominalInverseKinematics ik(arm.robot);
  Measure(state, arm, [&](int k) { return ik.Solve(arm.T[k], Eigen::VectorXd()).q; });
  state.SetLabel(ik.method());
}

void BM_Ik_KdlLma(benchmark::State& state, const std::string& file, int max_starts) {
  const Arm& arm = GetArm(file);
  const KDL::Chain chain = testing::KdlChain(arm.robot.model());
  KDL::ChainIkSolverPos_LMA solver(chain, 1e-12, 500, 1e-15);
  const int n = arm.robot.dof();
  Eigen::VectorXd middle(n);
  for (int j = 0; j < n; ++j) middle[j] = 0.5 * (arm.robot.Limit(j).first + arm.robot.Limit(j).second);
  Rng rng(99);
  KDL::JntArray q_init(n), q_out(n);
  Measure(state, arm, [&](int k) {
    const KDL::Frame target = testing::ToKdl(arm.T[k]);
    Eigen::VectorXd q = middle;
    for (int start = 0; start < max_starts; ++start) {
      Eigen::VectorXd init = middle;
      if (start > 0) {
        for (int j = 0; j < n; ++j) init[j] = rng.Uniform(arm.robot.Limit(j).first, arm.robot.Limit(j).second);
      }
      q_init.data = init;
      solver.CartToJnt(q_init, target, q_out);
      q = q_out.data;
      if (Solved(arm.robot, arm.T[k], q)) break;
    }
    return q;
  });
}

// The whole `kincal compensate --method analytic_derivative` on 2000 targets (nominal poses of random
// configurations within the limits), with the configurations as seeds or without seeds. The identified
// robot: the seed's for its arm, otherwise the nominal one with every length moved by up to 0.5 mm and
// every angle by up to 0.05 deg (seeded). Counter reached: converged within 1e-6 mm and 1e-8 rad.
void BM_CompensateCommand(benchmark::State& state, const std::string& file, bool seeds) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("kincal_ik_bench_" + file);
  std::filesystem::create_directories(dir);
  const std::string robots = std::string(KINCAL_SOURCE_DIR) + "/examples/robots/";
  const Robot nominal = ReadRobotFile(robots + file);
  const std::string identified_path = file == "seed_nominal.yaml" ? robots + "seed_identified.yaml"
                                                                   : (dir / "identified.yaml").string();
  const std::string targets = (dir / (seeds ? "seeded.csv" : "seedless.csv")).string();
  const std::string out = (dir / "joints.csv").string();
  Rng rng(2000);
  if (file != "seed_nominal.yaml") {
    Robot identified = nominal;
    Eigen::VectorXd p = identified.model().Parameters();
    const auto& info = identified.model().parameter_info();
    for (int i = 0; i < p.size(); ++i) {
      p[i] += info[i].kind == ParameterInfo::Kind::kLength ? rng.Uniform(-0.5e-3, 0.5e-3)
                                                           : rng.Uniform(-0.05, 0.05) * M_PI / 180;
    }
    identified.model().SetParameters(p);
    WriteRobotFile(identified, identified_path);
  }
  {
    std::ofstream f(targets);
    f.precision(17);
    f << "x_mm,y_mm,z_mm,qw,qx,qy,qz";
    if (seeds) for (int j = 1; j <= nominal.dof(); ++j) f << ",q" << j << "_rad";
    f << "\n";
    for (int k = 0; k < 2000; ++k) {
      Eigen::VectorXd q(nominal.dof());
      for (int j = 0; j < q.size(); ++j) q[j] = rng.Uniform(nominal.Limit(j).first, nominal.Limit(j).second);
      const Eigen::Isometry3d T = nominal.model().ForwardKinematics(q);
      const Eigen::Vector3d p = T.translation() * 1e3;
      const Eigen::Quaterniond quat(T.linear());
      f << p.x() << "," << p.y() << "," << p.z() << "," << quat.w() << "," << quat.x() << "," << quat.y() << "," << quat.z();
      if (seeds) for (int j = 0; j < q.size(); ++j) f << "," << q[j];
      f << "\n";
    }
  }
  const std::string command = std::string(KINCAL_CLI) + " compensate --nominal " + robots + file + " --identified " +
                              identified_path + " --targets " + targets + " --method analytic_derivative --out " + out +
                              " > /dev/null";
  for (auto _ : state) {
    if (std::system(command.c_str()) != 0) state.SkipWithError("kincal compensate failed");
  }
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  int reached = 0, rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    const size_t s = cells.size();
    // ..., status, iterations, position_error_mm, orientation_error_deg, seed_computed
    ++rows;
    reached += cells[s - 5] == "converged" && std::stod(cells[s - 3]) <= 1e-6 &&
               std::stod(cells[s - 2]) * M_PI / 180 <= 1e-8;
  }
  state.counters["reached"] = rows ? double(reached) / rows : 0.0;
}

const char* const kArms[] = {"seed_nominal.yaml", "irb120_mdh.yaml", "ur10_dh.yaml", "puma560_dh.yaml"};

void Register() {
  for (const char* arm : kArms) {
    const std::string name(arm, std::string(arm).find('.'));
    benchmark::RegisterBenchmark(("Ik_Kincal/" + name).c_str(), BM_Ik_Kincal, arm)->Iterations(3)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Ik_KdlLma/" + name).c_str(), BM_Ik_KdlLma, arm, 1)->Iterations(1)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Ik_KdlLmaRestarts/" + name).c_str(), BM_Ik_KdlLma, arm, 20)
        ->Iterations(1)->Unit(benchmark::kMillisecond);
  }
  for (const char* arm : kArms) {
    const std::string name(arm, std::string(arm).find('.'));
    benchmark::RegisterBenchmark(("CompensateCommand/seeds/" + name).c_str(), BM_CompensateCommand, arm, true)
        ->Iterations(3)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("CompensateCommand/seedless/" + name).c_str(), BM_CompensateCommand, arm, false)
        ->Iterations(3)->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  kincal::Register();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
