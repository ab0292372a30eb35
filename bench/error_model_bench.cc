// Error-model estimators on the speed case of the target: the seed's 6-joint arm, 1000 random poses seen by
// a tracker metres away (10 um noise, encoder counts), everything identifiable free (33 parameters:
// geometry, base, tool position, six ratios). Target: least_squares within 10 ms, and no
// slower than ceres in the same run. Adding an estimator to the comparison is one
// BENCHMARK_CAPTURE line at the bottom. The million-pose run shows that memory does not grow with the
// poses beyond the dataset itself (peak_rss_MB; about 350 MB of it is the Dataset's rows); skip it with
//   ./build/bench/kincal_error_model_bench --benchmark_filter='/1000$'
#include <fstream>
#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include "bench/smoke.h"
#include "estimators/error_model/normal_equations.h"
#include "estimators/estimator.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

namespace kincal {
namespace {

struct SpeedCase {
  Robot nominal;
  Dataset data;
};

const SpeedCase& Case(int poses) {
  static std::map<int, SpeedCase> cases;
  auto it = cases.find(poses);
  if (it != cases.end()) return it->second;
  SpeedCase c;
  c.nominal = ReadRobotFile(KINCAL_SOURCE_DIR "/examples/robots/seed_nominal.yaml");
  Robot truth = ReadRobotFile(KINCAL_SOURCE_DIR "/examples/robots/seed_identified.yaml");
  truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(1.8, -0.6, 0.4), Eigen::Vector3d(0.3, -0.2, 2.0)));
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = poses;
  so.noise_sigma = 10e-6;
  so.seed = 2024;
  c.data = Simulate(c.nominal, truth, so);
  return cases.emplace(poses, std::move(c)).first->second;
}

// Peak resident memory of this process, MB (Linux; 0 elsewhere).
double PeakRssMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kb = 0.0;
      status >> kb;
      return kb / 1024.0;
    }
  }
  return 0.0;
}

void BM_Estimator(benchmark::State& state, const std::string& name) {
  if (!Estimators().IsRegistered(name)) {
    state.SkipWithError((name + " is not registered").c_str());
    return;
  }
  const SpeedCase& c = Case(static_cast<int>(state.range(0)));
  const auto estimator = Estimators().Create(name);
  EstimationReport report;
  for (auto _ : state) {
    Robot identified;
    report = estimator->Estimate(c.nominal, c.data, &identified);
    benchmark::DoNotOptimize(identified);
  }
  state.counters["iterations"] = report.iterations;
  state.counters["final_rms_um"] = report.final_rms * 1e6;
  state.counters["free_parameters"] = report.details.value("free_parameters", 0);
  state.counters["peak_rss_MB"] = PeakRssMegabytes();
  if (report.status != EstimationStatus::kConverged) state.SkipWithError(report.BriefReport().c_str());
}

// Joint error terms held whole at zero must cost nothing: least_squares on the richest ur10 file
// (examples/robots/ur10_joint_errors.yaml: gravity, harmonic, backlash and approach terms, 96
// coefficients) with `fixed: [joint_errors]`, against the same robot without the terms (/0: plain,
// /1: terms fixed). Simulated: a perturbed truth seen by a tracker, 2000 random poses, 10 um noise.
// Target: /1 within 1.5x of /0.
struct FixedTermsCase {
  Robot rich, plain;
  Dataset data;
};

const FixedTermsCase& Ur10FixedTermsCase() {
  static const FixedTermsCase c = [] {
    FixedTermsCase out;
    out.rich = ReadRobotFile(KINCAL_SOURCE_DIR "/examples/robots/ur10_joint_errors.yaml");
    out.plain = out.rich;
    out.plain.joint_errors.terms.clear();
    Robot truth = out.plain;
    Eigen::VectorXd values = truth.model().Parameters();
    Rng rng(77);
    for (int j = 0; j < values.size(); ++j) values[j] += rng.Uniform(-1, 1) * 2e-4;  // 0.2 mm, 0.2 mrad
    truth.model().SetParameters(values);
    truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(2.2, -1.3, 0.1), Eigen::Vector3d(0.01, -0.02, 2.6)));
    SimulatorOptions so;
    so.protocol = "random";
    so.poses = 2000;
    so.noise_sigma = 10e-6;
    so.seed = 2025;
    out.data = Simulate(out.plain, truth, so);
    return out;
  }();
  return c;
}

void BM_FixedJointErrorTerms(benchmark::State& state) {
  const FixedTermsCase& c = Ur10FixedTermsCase();
  const bool fixed = state.range(0) != 0;
  YAML::Node options;
  options["max_iterations"] = 200;
  if (fixed) options["fixed"].push_back("joint_errors");
  const auto estimator = Estimators().Create("least_squares", options);
  EstimationReport report;
  for (auto _ : state) {
    Robot identified;
    report = estimator->Estimate(fixed ? c.rich : c.plain, c.data, &identified);
    benchmark::DoNotOptimize(identified);
  }
  state.counters["iterations"] = report.iterations;
  state.counters["final_rms_um"] = report.final_rms * 1e6;
  state.counters["free_parameters"] = report.details.value("free_parameters", 0);
  if (report.status != EstimationStatus::kConverged) state.SkipWithError(report.BriefReport().c_str());
}

// One pass over the data: cost, J^T r and J^T J (what a Gauss-Newton iteration costs).
void BM_NormalEquationsPass(benchmark::State& state) {
  const SpeedCase& c = Case(static_cast<int>(state.range(0)));
  const ErrorModelProblem problem(c.nominal, c.nominal, c.data, ErrorModelOptions());
  const Eigen::VectorXd x = problem.InitialX();
  for (auto _ : state) {
    NormalEquations ne = AccumulateNormalEquations(problem, x);
    benchmark::DoNotOptimize(ne);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

}  // namespace

BENCHMARK_CAPTURE(BM_Estimator, least_squares, std::string("least_squares"))->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, ceres, std::string("ceres"))->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, nlopt, std::string("nlopt"))->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, ipopt, std::string("ipopt"))->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, least_squares, std::string("least_squares"))
    ->Arg(BenchSize(1000000, 20000))
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_FixedJointErrorTerms)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NormalEquationsPass)->Arg(1000)->Arg(BenchSize(100000, 10000))->Unit(benchmark::kMillisecond);

}  // namespace kincal

BENCHMARK_MAIN();
