// `kincal check` (doctor/doctor.h) on 10,000 rows. Target: <= 10 s. Simulated UR10 poses (random within
// the limits, 20 um noise, a tracker 2 m away, the tool 150 mm from the flange): clean data (one round of
// hypotheses), and the worst case, three faults at once (every round of hypotheses runs, then the tool,
// outlier and still-joint checks): metres read as millimetres, joints 2 and 3 swapped, 20 gross outliers.
//   ./build/bench/kincal_doctor_bench
#include <benchmark/benchmark.h>

#include "doctor/doctor.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

namespace kincal {
namespace {

struct Case {
  Robot nominal;
  Dataset data;
};

Case TenThousandRows() {
  Case c{ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/ur10_dh.yaml"), {}};
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Eigen::Vector3d(0.03, 0.06, 0.15);
  c.nominal.model().SetTool(tool);
  Robot truth = c.nominal;
  Eigen::VectorXd p = truth.model().Parameters();
  Rng rng(7);
  for (int i = 0; i < p.size(); ++i) p[i] += 5e-4 * rng.Normal();
  truth.model().SetParameters(p);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(2.0, -0.5, -0.4);
  truth.model().SetBase(base);
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = 10000;
  so.noise_sigma = 20e-6;
  c.data = Simulate(c.nominal, truth, so);
  return c;
}

void Run(benchmark::State& state, const Case& c) {
  size_t findings = 0;
  for (auto _ : state) findings = doctor::Diagnose(c.nominal, c.data).size();
  state.counters["rows"] = static_cast<double>(c.data.rows.size());
  state.counters["findings"] = static_cast<double>(findings);  // 0 clean, 3 with three faults
}

void BM_CheckClean(benchmark::State& state) {
  static const Case c = TenThousandRows();
  Run(state, c);
}
BENCHMARK(BM_CheckClean)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

void BM_CheckThreeFaults(benchmark::State& state) {
  static const Case c = [] {
    Case f = TenThousandRows();
    for (auto& m : f.data.rows) {
      m.p *= 1e-3;
      std::swap(m.q[1], m.q[2]);
    }
    for (size_t i = 100; i < f.data.rows.size(); i += 500) f.data.rows[i].p += Eigen::Vector3d(5e-5, 0, 0);
    return f;
  }();
  Run(state, c);
}
BENCHMARK(BM_CheckThreeFaults)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace
}  // namespace kincal

BENCHMARK_MAIN();
