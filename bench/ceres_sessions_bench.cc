// The `ceres` estimator's linear solvers on session data: the seed's arm measured from S tracker stations
// (each session its own base block, 50 poses per station, 10 um noise). Rows of different sessions touch
// different base blocks, so J^T J has S (S - 1) zero 6x6 blocks: sparse normal Cholesky (SuiteSparse,
// what linear_solver "auto" picks) against dense QR, which treats those zeros as numbers.
//   ./build/bench/kincal_ceres_sessions_bench
#include <cmath>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "estimators/estimator.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

namespace kincal {
namespace {

struct SessionCase {
  Robot nominal;
  Dataset data;
};

const SessionCase& Case(int sessions) {
  static std::map<int, SessionCase> cases;
  auto it = cases.find(sessions);
  if (it != cases.end()) return it->second;
  SessionCase c;
  c.nominal = ReadRobotFile(KINCAL_SOURCE_DIR "/examples/robots/seed_nominal.yaml");
  Robot truth = ReadRobotFile(KINCAL_SOURCE_DIR "/examples/robots/seed_identified.yaml");
  truth.model().SetBase(PoseFromXyzRpy(Eigen::Vector3d(1.8, -0.6, 0.4), Eigen::Vector3d(0.3, -0.2, 2.0)));
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = 50 * sessions;
  so.noise_sigma = 10e-6;
  so.seed = 77;
  c.data = Simulate(c.nominal, truth, so);
  for (size_t i = 0; i < c.data.rows.size(); ++i) {
    Measurement& m = c.data.rows[i];
    m.session = static_cast<int>(i) % sessions;
    if (m.session == 0) continue;
    // Station k stands elsewhere around the arm: re-measure from its frame.
    const double angle = 2.0 * M_PI * m.session / sessions;
    const Eigen::Vector3d station(2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.3);
    const Eigen::Isometry3d T_k_base = PoseFromXyzRpy(station, Eigen::Vector3d(0.0, 0.0, angle));
    m.p = T_k_base * truth.model().base().inverse() * m.p;
  }
  return cases.emplace(sessions, std::move(c)).first->second;
}

void BM_CeresSessions(benchmark::State& state, const std::string& linear_solver) {
  const SessionCase& c = Case(static_cast<int>(state.range(0)));
  YAML::Node options;
  options["linear_solver"] = linear_solver;
  const auto estimator = Estimators().Create("ceres", options);
  EstimationReport report;
  for (auto _ : state) {
    Robot identified;
    report = estimator->Estimate(c.nominal, c.data, &identified);
    benchmark::DoNotOptimize(identified);
  }
  state.counters["iterations"] = report.iterations;
  state.counters["free_parameters"] = report.details.value("free_parameters", 0);
  state.counters["linear_solver_ms"] = report.details["times_s"].value("linear_solver", 0.0) * 1e3;
  if (report.status != EstimationStatus::kConverged) state.SkipWithError(report.BriefReport().c_str());
}

}  // namespace

BENCHMARK_CAPTURE(BM_CeresSessions, sparse_normal_cholesky, std::string("sparse_normal_cholesky"))
    ->Arg(5)
    ->Arg(20)
    ->Arg(40)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CeresSessions, dense_qr, std::string("dense_qr"))
    ->Arg(5)
    ->Arg(20)
    ->Arg(40)
    ->Unit(benchmark::kMillisecond);

}  // namespace kincal

BENCHMARK_MAIN();
