// The whole `kincal compensate --method analytic_derivative` on 2000 targets without seeds against the same
// targets with seeds (at most 3x), for the seed's arm, IRB 120, UR10 and Puma 560.
//
// Two kinds of targets, each the pose of a random configuration within the joint limits (seed 2000):
//  - reachable: the identified (real) arm's pose, which the arm reaches by construction;
//  - nominal: the nominal arm's pose, as first measured. Next to a fold of the nominal workspace
//    the identified arm does not reach such a pose on any configuration within its limits: those count
//    as not reached whatever the compensator does.
// Seeds, in the seeded run: the controller's solution, i.e. the nominal inverse kinematics on the branch
// nearest the configuration (for nominal targets that is the configuration itself; for reachable ones
// next to a fold of the nominal workspace the nominal arm has no exact solution and the best it found is
// the seed). Identified robot: the seed's for its arm
// (seed_identified.yaml), otherwise the nominal one with every length moved by up to 0.5 mm and every
// angle by up to 0.05 deg (seeded). Counters: reached = converged within 1e-6 mm and 1e-8 rad (the
// acceptance criterion), changed = reached on another branch than the controller's, child_cpu_ms = the
// command's CPU time (user + system; robust under load, unlike the wall time).
//
//   ./build/bench/kincal_seedless_compensation_bench --benchmark_counters_tabular=true
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/smoke.h"
#include "compensators/compensator.h"
#include "framework/math.h"
#include "robot/nominal_ik.h"
#include "framework/random.h"
#include "robot/robot_file.h"

namespace kincal {
namespace {

const int kTargets = BenchSize(2000, 200);

double ChildCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Writes the identified robot (when it is made here) and both targets files; returns the identified path.
// far: the seed's arm as a tracker sees it (the frame contract, compensators/compensator.h): the nominal
// file with base and tool identity (written to *nominal_path), the identified robot 1.5 m away, turned
// 90 deg about z, with a 121 mm tool; seeds from the controller (the nominal geometry placed there).
std::string PrepareFiles(const std::string& file, bool reachable, const std::filesystem::path& dir, bool far,
                         std::string* nominal_path) {
  const std::string robots = std::string(KINCAL_SOURCE_DIR) + "/examples/robots/";
  Robot nominal = ReadRobotFile(robots + file);
  *nominal_path = robots + file;
  if (far) {
    nominal.model().SetTool(Eigen::Isometry3d::Identity());
    *nominal_path = (dir / "nominal.yaml").string();
    WriteRobotFile(nominal, *nominal_path);
  }
  Rng rng(2000);
  Robot identified = nominal;
  std::string identified_path = robots + "seed_identified.yaml";
  if (file == "seed_nominal.yaml") {
    identified = ReadRobotFile(identified_path);
    if (far) {
      identified.model().SetBase(PoseFromXyzRpy({1.2, 0.9, 0.1}, {0.0, 0.0, M_PI / 2}));
      identified.model().SetTool(PoseFromXyzRpy({0.04, 0.03, 0.11}, {0.0, 0.2, 0.0}));
      identified_path = (dir / "identified.yaml").string();
      WriteRobotFile(identified, identified_path);
    }
  } else {
    Eigen::VectorXd p = identified.model().Parameters();
    const auto& info = identified.model().parameter_info();
    for (int i = 0; i < p.size(); ++i) {
      p[i] += info[i].kind == ParameterInfo::Kind::kLength ? rng.Uniform(-0.5e-3, 0.5e-3)
                                                           : rng.Uniform(-0.05, 0.05) * M_PI / 180;
    }
    identified.model().SetParameters(p);
    identified_path = (dir / "identified.yaml").string();
    WriteRobotFile(identified, identified_path);
  }
  const Robot& posed = reachable ? identified : nominal;
  const NominalInverseKinematics controller(ControllerRobot(nominal, identified));
  std::ofstream seeded(dir / "seeded.csv"), seedless(dir / "seedless.csv");
  for (std::ofstream* f : {&seeded, &seedless}) {
    f->precision(17);
    *f << "x_mm,y_mm,z_mm,qw,qx,qy,qz";
  }
  for (int j = 1; j <= nominal.dof(); ++j) seeded << ",q" << j << "_rad";
  seeded << "\n";
  seedless << "\n";
  for (int k = 0; k < kTargets; ++k) {
    Eigen::VectorXd q(nominal.dof());
    for (int j = 0; j < q.size(); ++j) q[j] = rng.Uniform(nominal.Limit(j).first, nominal.Limit(j).second);
    const Eigen::Isometry3d T = posed.model().ForwardKinematics(q);
    const Eigen::Vector3d p = T.translation() * 1e3;
    const Eigen::Quaterniond quat(T.linear());
    for (std::ofstream* f : {&seeded, &seedless}) {
      *f << p.x() << "," << p.y() << "," << p.z() << "," << quat.w() << "," << quat.x() << "," << quat.y() << ","
         << quat.z();
    }
    const Eigen::VectorXd seed = reachable ? controller.Solve(T, q).q : q;
    for (int j = 0; j < q.size(); ++j) seeded << "," << seed[j];
    seeded << "\n";
    seedless << "\n";
  }
  return identified_path;
}

void BM_CompensateCommand(benchmark::State& state, const std::string& file, bool reachable, bool seeds, bool far) {
  const std::string stem = file.substr(0, file.find('.')) + (far ? "_far_base" : "");
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("kincal_seedless_bench_" + stem + (reachable ? "_reachable" : "_nominal"));
  std::filesystem::create_directories(dir);
  std::string nominal;
  const std::string identified = PrepareFiles(file, reachable, dir, far, &nominal);
  const std::string out = (dir / (seeds ? "seeded_joints.csv" : "seedless_joints.csv")).string();
  const std::string command = std::string(KINCAL_CLI) + " compensate --nominal " + nominal + " --identified " +
                              identified + " --targets " + (dir / (seeds ? "seeded.csv" : "seedless.csv")).string() +
                              " --method analytic_derivative --out " + out + " > " + out + ".log";
  double cpu = 0.0;
  for (auto _ : state) {
    const double c0 = ChildCpuSeconds();
    if (std::system(command.c_str()) != 0) state.SkipWithError("kincal compensate failed");
    cpu += ChildCpuSeconds() - c0;
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
    reached +=
        cells[s - 5] == "converged" && std::stod(cells[s - 3]) <= 1e-6 && std::stod(cells[s - 2]) * M_PI / 180 <= 1e-8;
  }
  std::ifstream log(out + ".log");
  std::stringstream text;
  text << log.rdbuf();
  const std::string summary = text.str();
  const size_t at = summary.find(" reached on another branch");
  int changed = 0;
  if (at != std::string::npos) {
    size_t begin = summary.rfind(' ', at - 1);
    changed = std::atoi(summary.c_str() + begin + 1);
  }
  state.counters["reached"] = rows ? double(reached) / rows : 0.0;
  state.counters["changed"] = changed;
  state.counters["child_cpu_ms"] = 1e3 * cpu / state.iterations();
}

void Register() {
  for (const char* arm : {"seed_nominal.yaml", "irb120_mdh.yaml", "ur10_dh.yaml", "puma560_dh.yaml"}) {
    const std::string stem(arm, std::string(arm).find('.'));
    for (bool reachable : {true, false}) {
      for (bool seeds : {true, false}) {
        const std::string name = std::string("CompensateCommand/") + (reachable ? "reachable/" : "nominal/") +
                                 (seeds ? "seeds/" : "seedless/") + stem;
        benchmark::RegisterBenchmark(name.c_str(), BM_CompensateCommand, arm, reachable, seeds, false)
            ->Iterations(BenchSize(3, 1))
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
  for (bool seeds : {true, false}) {
    const std::string name =
        std::string("CompensateCommand/reachable/") + (seeds ? "seeds/" : "seedless/") + "seed_nominal_far_base";
    benchmark::RegisterBenchmark(name.c_str(), BM_CompensateCommand, "seed_nominal.yaml", true, seeds, true)
        ->Iterations(BenchSize(3, 1))
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
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
