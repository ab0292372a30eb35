// Compensators against orocos KDL's ChainIkSolverPos_LMA, same targets, same identified model, same seeds,
// same run; the seed's "1e-12 in 4 iterations" claim; joint_space's accuracy, speed, memory and build time on
// the seed's arm with a tracker base and a marker;
// the whole `kincal compensate` command on 20000 targets.
//
//   ./build/bench/kincal_compensators_bench                         everything
//   ./build/bench/kincal_compensators_bench --benchmark_filter=Kdl  one family
//
// Targets: 1000 random configurations of the identified seed arm (Table 2) within its joint limits, their
// poses, and the nominal arm's (Table 1) inverse kinematics from the true configuration as seeds
// (compensators/common/random_targets.h). KDL gets the identified arm as a chain built from the model's
// frames at q = 0 (checked against our forward kinematics to 1e-15 m) and the same seeds; "matched" asks
// it for our accuracy (|weighted error| < 1e-12 with unit weights: m and rad), "default" uses its
// defaults (eps 1e-5 on the error weighted by (1, 1, 1, 0.01, 0.01, 0.01)).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include "compensators/analytic_derivative/analytic_derivative_compensator.h"
#include "compensators/common/random_targets.h"
#include "compensators/joint_space/joint_space_compensator.h"
#include "compensators/compensator.h"
#include "framework/math.h"
#include "robot/robot_file.h"

namespace kincal {
namespace {

struct Setup {
  Robot nominal, identified;
  RandomTargets all;  // every reachable target
};

// The seed's arm as a real calibration sees it (as tests/compensators/tracked_arm.h): a tracker base
// 1.5 m away and a marker 120 mm off the flange, known to the controller as set up, a few mm and mrad
// off in the identified robot.
const Setup& GetTrackedSetup() {
  static const Setup setup = [] {
    Setup s;
    s.nominal = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/seed_nominal.yaml");
    s.identified = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/seed_identified.yaml");
    const Eigen::Isometry3d T_meas_base = PoseFromXyzRpy({1.2, -0.85, 0.35}, {0.02, -0.015, 2.4});
    const Eigen::Isometry3d T_flange_tool = PoseFromXyzRpy({0.04, -0.03, 0.11}, {0.0, 0.3, 0.0});
    s.nominal.model().SetBase(T_meas_base);
    s.nominal.model().SetTool(T_flange_tool);
    s.identified.model().SetBase(T_meas_base * PoseFromXyzRpy({0.0031, -0.0024, 0.0017}, {0.0012, -0.0008, 0.0021}));
    s.identified.model().SetTool(T_flange_tool * PoseFromXyzRpy({0.0006, 0.0009, -0.0011}, {0.003, -0.002, 0.001}));
    RandomTargetOptions o;
    o.count = 2000;
    o.seed = 12;
    s.all = MakeRandomTargets(s.nominal, s.identified, o);
    return s;
  }();
  return setup;
}

const Setup& GetSetup() {
  static const Setup setup = [] {
    Setup s;
    s.nominal = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/seed_nominal.yaml");
    s.identified = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/seed_identified.yaml");
    RandomTargetOptions o;
    o.count = 1000;
    o.seed = 2015;
    s.all = MakeRandomTargets(s.nominal, s.identified, o);
    return s;
  }();
  return setup;
}

KDL::Frame ToKdl(const Eigen::Isometry3d& T) {
  KDL::Frame F;
  for (int i = 0; i < 3; ++i) {
    F.p(i) = T.translation()[i];
    for (int j = 0; j < 3; ++j) F.M(i, j) = T.linear()(i, j);
  }
  return F;
}

// MDH: joint i turns about z of frame i at the end of its link, so the chain is frame 1 at q = 0, then per
// joint a RotZ segment whose tip is the next frame (the tool after the last joint).
KDL::Chain KdlChain(const Robot& robot) {
  if (robot.model().convention() != "mdh") throw std::invalid_argument("KdlChain: mdh models only");
  const std::vector<Eigen::Isometry3d> F = robot.model().FramePoses(Eigen::VectorXd::Zero(robot.dof()));
  KDL::Chain chain;
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::Fixed), ToKdl(F[1])));
  for (int i = 1; i <= robot.dof(); ++i) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), ToKdl(F[i].inverse() * F[i + 1])));
  }
  return chain;
}

// Google Benchmark calls a benchmark function several times while it sizes the run: tables are built once.
const Compensator& PreparedCompensator(const std::string& method, const std::string& options_yaml) {
  static std::map<std::string, std::unique_ptr<Compensator>> cache;
  std::unique_ptr<Compensator>& c = cache[method + options_yaml];
  if (!c) {
    c = Compensators().Create(method, YAML::Load(options_yaml));
    c->Prepare(GetSetup().nominal, GetSetup().identified);
  }
  return *c;
}

void BM_Compensate(benchmark::State& state, const std::string& method, const std::string& options_yaml) {
  const Setup& s = GetSetup();
  const Compensator* c = &PreparedCompensator(method, options_yaml);
  size_t k = 0;
  double iterations = 0, solves = 0, converged = 0, max_position = 0;
  for (auto _ : state) {
    const CompensationResult r = c->Compensate(s.all.targets[k]);
    benchmark::DoNotOptimize(r.q_command.data());
    iterations += r.report.iterations;
    converged += r.report.status == CompensationStatus::kConverged;
    max_position = std::max(max_position, r.report.position_error);
    ++solves;
    k = (k + 1) % s.all.targets.size();
  }
  state.counters["iterations"] = iterations / solves;
  state.counters["converged"] = converged / solves;
  state.counters["max_pos_mm"] = max_position * 1e3;
}

void BM_KdlLma(benchmark::State& state, bool matched, bool tracked) {
  const Setup& s = tracked ? GetTrackedSetup() : GetSetup();
  const KDL::Chain chain = KdlChain(s.identified);
  Eigen::Matrix<double, 6, 1> L;
  L << 1, 1, 1, 0.01, 0.01, 0.01;
  if (matched) L.setOnes();
  {
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::JntArray q(s.identified.dof());
    q.data = s.all.targets[0].seed;
    KDL::Frame F;
    fk.JntToCart(q, F);
    const Eigen::Isometry3d T = s.identified.model().ForwardKinematics(q.data);
    const double gap = (Eigen::Vector3d(F.p.x(), F.p.y(), F.p.z()) - T.translation()).norm();
    if (!(gap < 1e-12)) {
      state.SkipWithError("the KDL chain does not reproduce the model");
      return;
    }
  }
  KDL::ChainIkSolverPos_LMA solver(chain, L, matched ? 1e-12 : 1e-5, 500, 1e-15);
  std::vector<KDL::Frame> goals;
  for (const auto& t : s.all.targets) goals.push_back(ToKdl(t.T_meas_tool));
  KDL::JntArray q_init(s.identified.dof()), q_out(s.identified.dof());
  size_t k = 0;
  double iterations = 0, solves = 0, converged = 0, max_position = 0;
  for (auto _ : state) {
    q_init.data = s.all.targets[k].seed;
    const int rc = solver.CartToJnt(q_init, goals[k], q_out);
    benchmark::DoNotOptimize(q_out.data.data());
    iterations += solver.lastNrOfIter;
    converged += rc == KDL::SolverI::E_NOERROR;
    max_position = std::max(max_position, solver.lastTransDiff);
    ++solves;
    k = (k + 1) % s.all.targets.size();
  }
  state.counters["iterations"] = iterations / solves;
  state.counters["converged"] = converged / solves;
  state.counters["max_pos_mm"] = max_position * 1e3;
}

// joint_space on the tracked arm (2000 random reachable targets, singular neighbourhoods included):
// the fraction within 0.05 mm and 1e-4 rad (>= 95 %), time per Compensate() (<= 2 us),
// memory (<= 50 MB) and the build (<= 10 s on one core, BM_JointSpacePrepare). KDL on the same targets:
// BM_KdlLma/tracked_*.
void BM_JointSpaceTracked(benchmark::State& state, const std::string& options_yaml) {
  const Setup& s = GetTrackedSetup();
  auto c = Compensators().Create("joint_space", YAML::Load(options_yaml));
  c->Prepare(s.nominal, s.identified);
  const auto& info = dynamic_cast<const JointSpaceCompensator&>(*c).table_info();
  std::vector<double> mm;
  double within = 0, converged = 0;
  for (const auto& t : s.all.targets) {
    const CompensationResult r = c->Compensate(t);
    mm.push_back(r.report.position_error * 1e3);
    within += r.report.position_error <= 0.05e-3 && r.report.orientation_error <= 1e-4;
    converged += r.report.status == CompensationStatus::kConverged;
  }
  std::sort(mm.begin(), mm.end());
  size_t k = 0;
  for (auto _ : state) {
    const CompensationResult r = c->Compensate(s.all.targets[k]);
    benchmark::DoNotOptimize(r.q_command.data());
    k = (k + 1) % s.all.targets.size();
  }
  const double n = static_cast<double>(s.all.targets.size());
  state.counters["within_frac"] = within / n;
  state.counters["conv_frac"] = converged / n;
  state.counters["p50_mm"] = mm[mm.size() / 2];
  state.counters["p95_mm"] = mm[static_cast<size_t>(0.95 * mm.size())];
  state.counters["max_mm"] = mm.back();
  state.counters["MB"] = info.memory_bytes / 1e6;
  state.counters["build_s"] = info.build_seconds;
}

// The offline build of the expansion (one core: Prepare is single-threaded).
void BM_JointSpacePrepare(benchmark::State& state) {
  const Setup& s = GetTrackedSetup();
  for (auto _ : state) {
    JointSpaceCompensator c;
    c.Prepare(s.nominal, s.identified);
    benchmark::DoNotOptimize(c.table_info().terms);
  }
}

// The whole command: write 20000 targets (with the controller's seeds), run `kincal compensate` (read,
// prepare, solve, write) as a process.
void BM_CompensateCommand(benchmark::State& state, const std::string& method) {
  const Setup& s = GetSetup();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "kincal_compensators_bench";
  std::filesystem::create_directories(dir);
  const std::string targets = (dir / "targets.csv").string(), out = (dir / "joints.csv").string();
  if (!std::filesystem::exists(targets)) {
    RandomTargetOptions o;
    o.count = 20000;
    o.seed = 20000;
    const RandomTargets many = MakeRandomTargets(s.nominal, s.identified, o);
    std::ofstream f(targets);
    f.precision(17);
    f << "x_mm,y_mm,z_mm,qw,qx,qy,qz,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n";
    for (const auto& t : many.targets) {
      const Eigen::Vector3d p = t.T_meas_tool.translation() * 1e3;
      const Eigen::Quaterniond quat(t.T_meas_tool.linear());
      f << p.x() << "," << p.y() << "," << p.z() << "," << quat.w() << "," << quat.x() << "," << quat.y() << ","
        << quat.z();
      for (int j = 0; j < t.seed.size(); ++j) f << "," << t.seed[j] * 180 / M_PI;
      f << "\n";
    }
  }
  const std::string robots = std::string(KINCAL_SOURCE_DIR) + "/examples/robots/";
  const std::string command = std::string(KINCAL_CLI) + " compensate --nominal " + robots +
                              "seed_nominal.yaml --identified " + robots + "seed_identified.yaml --targets " + targets +
                              " --method " + method + " --out " + out + " > /dev/null";
  for (auto _ : state) {
    if (std::system(command.c_str()) != 0) state.SkipWithError("kincal compensate failed");
  }
  state.counters["targets"] = 20000;
}

// The seed's claim (METHOD.md 4): 1e-12 mm and 1e-12 deg in 4 iterations. Runs with those tolerances
// and records, per target, the first iteration meeting a threshold.
void PrintSeedClaimStatistics() {
  const Setup& s = GetSetup();
  struct Variant {
    const char* name;
    bool plain;
  };
  std::printf("\nThe seed's claim, %zu random reachable targets of the seed arm (nominal seeds):\n",
              s.all.targets.size());
  std::printf("%-34s %12s %12s %12s %12s %10s\n", "analytic_derivative", "<=4 it 1e-12", "<=4 it 1e-9", "ever 1e-12",
              "floor p50 m", "median it");
  for (const Variant& v : {Variant{"default (0.5 m, damped)", false}, Variant{"plain (paper: SI, A^+ B)", true}}) {
    AnalyticDerivativeCompensator::Options o;
    o.plain = v.plain;
    o.iteration.position_tolerance = 1e-15;                    // 1e-12 mm
    o.iteration.orientation_tolerance = 1e-12 * M_PI / 180.0;  // 1e-12 deg
    o.iteration.max_iterations = 12;
    AnalyticDerivativeCompensator c(o);
    c.Prepare(s.nominal, s.identified);
    int claim4 = 0, tight4 = 0, ever = 0;
    std::vector<double> floors, first_tight;
    for (const auto& t : s.all.targets) {
      const CompensationResult r = c.Compensate(t);
      const auto& ph = r.report.position_history;
      const auto& oh = r.report.orientation_history;
      int first_claim = -1, first_1e9 = -1;
      double floor = INFINITY;
      for (size_t i = 0; i < ph.size(); ++i) {
        floor = std::min(floor, ph[i]);
        if (first_claim < 0 && ph[i] <= 1e-15 && oh[i] <= 1e-12 * M_PI / 180.0) first_claim = static_cast<int>(i);
        if (first_1e9 < 0 && ph[i] <= 1e-12 && oh[i] <= 1e-12) first_1e9 = static_cast<int>(i);
      }
      claim4 += first_claim >= 0 && first_claim <= 4;
      tight4 += first_1e9 >= 0 && first_1e9 <= 4;
      ever += first_claim >= 0;
      floors.push_back(floor);
      first_tight.push_back(first_1e9 < 0 ? 99 : first_1e9);
    }
    std::sort(floors.begin(), floors.end());
    std::sort(first_tight.begin(), first_tight.end());
    const double n = static_cast<double>(s.all.targets.size());
    std::printf("%-34s %11.1f%% %11.1f%% %11.1f%% %12.2e %10.0f\n", v.name, 100 * claim4 / n, 100 * tight4 / n,
                100 * ever / n, floors[floors.size() / 2], first_tight[first_tight.size() / 2]);
  }
  std::printf(
      "  <=4 it 1e-12: 1e-12 mm and 1e-12 deg within 4 iterations; <=4 it 1e-9: 1e-9 mm and 1e-12 rad;\n"
      "  ever 1e-12: the claim's accuracy at any iteration (12 at most); floor: smallest position error.\n\n");
}

// Collects the time per benchmark to print the ratios against KDL at the end: CPU time (robust when other
// processes share the machine) and real time.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Iteration && !run.error_occurred) {
        times_[run.benchmark_name()] = {run.GetAdjustedCPUTime(), run.GetAdjustedRealTime()};
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void PrintRatios() const {
    const auto kdl = times_.find("BM_KdlLma/matched");
    const auto kdl_default = times_.find("BM_KdlLma/default");
    if (kdl == times_.end() || kdl_default == times_.end()) return;
    std::printf("\nPer-target time relative to KDL ChainIkSolverPos_LMA (same run, same targets and seeds):\n");
    std::printf("%-40s %10s %10s | %10s %10s | %10s %10s\n", "benchmark", "cpu ns", "real ns", "cpu/match",
                "real/match", "cpu/deflt", "real/deflt");
    for (const auto& [name, t] : times_) {
      if (name.rfind("BM_Compensate/", 0) != 0 && name.rfind("BM_JointSpaceTracked/", 0) != 0 &&
          name.rfind("BM_KdlLma/", 0) != 0) {
        continue;
      }
      std::printf("%-40s %10.0f %10.0f | %10.4f %10.4f | %10.4f %10.4f\n", name.c_str(), t.first, t.second,
                  t.first / kdl->second.first, t.second / kdl->second.second, t.first / kdl_default->second.first,
                  t.second / kdl_default->second.second);
    }
  }

 private:
  std::map<std::string, std::pair<double, double>> times_;  // cpu, real
};

BENCHMARK_CAPTURE(BM_Compensate, none, "none", "{}");
BENCHMARK_CAPTURE(BM_Compensate, analytic_derivative, "analytic_derivative", "{}");
BENCHMARK_CAPTURE(BM_Compensate, analytic_derivative_plain, "analytic_derivative", "{plain: true}");
BENCHMARK_CAPTURE(BM_Compensate, jacobian, "jacobian", "{}");
BENCHMARK_CAPTURE(BM_Compensate, joint_space, "joint_space", "{}");
BENCHMARK_CAPTURE(BM_KdlLma, matched, true, false);
BENCHMARK_CAPTURE(BM_KdlLma, default, false, false);
BENCHMARK_CAPTURE(BM_KdlLma, tracked_matched, true, true);
BENCHMARK_CAPTURE(BM_KdlLma, tracked_default, false, true);
BENCHMARK_CAPTURE(BM_JointSpaceTracked, default, "{}");
BENCHMARK_CAPTURE(BM_JointSpaceTracked, only_cut_steps_singular, "{singular_ratio: 0}");
BENCHMARK_CAPTURE(BM_JointSpaceTracked, two_steps, "{steps: 2}");
BENCHMARK_CAPTURE(BM_JointSpaceTracked, four_steps, "{steps: 4}");
BENCHMARK(BM_JointSpacePrepare)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CompensateCommand, analytic_derivative_20000, "analytic_derivative")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_CompensateCommand, jacobian_20000, "jacobian")->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_CompensateCommand, joint_space_20000, "joint_space")->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  kincal::PrintSeedClaimStatistics();
  kincal::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatios();
  benchmark::Shutdown();
  return 0;
}
