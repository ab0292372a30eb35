// `kincal filter` on a RAPID module of 10,000 targets for the IRB 120 (target: <= 0.2 s on one core),
// beside `compensate`'s work on the same targets: analytic_derivative from the controller's solutions
// (seeds), without reading or writing a program. Identified robot: the nominal one with every length
// moved by up to 0.5 mm and every angle by up to 0.05 deg (seeded), its base 1.5 m away and turned 90 deg,
// a 118 mm tool. Targets: poses of random configurations within the limits (well conditioned), written
// as robtargets (declared and inline, confdata of the configuration), every 5th a jointtarget.
//
//   ./build/bench/kincal_filter_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "compensators/common/random_targets.h"
#include "compensators/compensator.h"
#include "framework/math.h"
#include "framework/random.h"
#include "programs/filter.h"
#include "robot/robot_file.h"
#include "tests/programs/programs_fixture.h"

namespace kincal {
namespace {

constexpr int kTargets = 10000;

struct Setup {
  Robot nominal = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/irb120_mdh.yaml");
  Robot identified = testing::Identified(nominal, 7);
  Robot controller = ControllerRobot(nominal, identified);
  std::vector<Eigen::VectorXd> qs = testing::Configurations(controller, kTargets, 1);
  std::string program = testing::RapidModule(controller, qs, 5);
  std::vector<CompensationTarget> targets;
  Setup() {
    for (const Eigen::VectorXd& q : qs) {
      CompensationTarget t;
      t.T_meas_tool = controller.model().ForwardKinematics(q);
      t.seed = q;
      targets.push_back(t);
    }
  }
};

const Setup& S() {
  static const Setup s;
  return s;
}

void BM_FilterRapid(benchmark::State& state) {
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat("rapid");
  const ProgramFilter filter(S().nominal, S().identified,
                             Compensators().Create("analytic_derivative", YAML::Load("{}")), {}, format->convention());
  int filtered = 0;
  for (auto _ : state) {
    const FilteredProgram out = filter.Filter(*format, S().program, "bench.mod");
    filtered = out.report.filtered;
    benchmark::DoNotOptimize(out.text.data());
  }
  state.counters["targets"] = kTargets;
  state.counters["filtered"] = filtered;
}
BENCHMARK(BM_FilterRapid)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void BM_CompensateSameTargets(benchmark::State& state) {
  const auto compensator = Compensators().Create("analytic_derivative", YAML::Load("{}"));
  compensator->Prepare(S().nominal, S().identified);
  int converged = 0;
  for (auto _ : state) {
    converged = 0;
    Eigen::VectorXd previous;
    for (CompensationTarget t : S().targets) {
      t.previous_command = previous;
      const CompensationResult r = compensator->Compensate(t);
      converged += r.report.status == CompensationStatus::kConverged;
      previous = r.q_command;
    }
  }
  state.counters["targets"] = kTargets;
  state.counters["converged"] = converged;
}
BENCHMARK(BM_CompensateSameTargets)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace
}  // namespace kincal

BENCHMARK_MAIN();
