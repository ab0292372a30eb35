// Per-row cost of the joint-level regressors with every derivative a fit asks for (joint angles, the
// previous pose's, the model parameters): EvaluateJointErrorMap (each gravity regressor moved along each
// twist on its own) against PreparedRegressors::EvaluateMap (one pass per row, models/joint_error_regressors.h),
// same rows, same run. Robots: the UR10 and IRB 120 example files with joint-level terms (gravity on joints
// 2-5, approach terms; the UR10 also harmonic and backlash terms), coefficients random within 1e-3 (seed 3),
// 999 rows of random joints within the limits, each with the row before as its previous pose. Counter:
// per_row (seconds of process CPU time).
//
//   ./build/bench/kincal_joint_error_regressors_bench
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "framework/random.h"
#include "models/joint_error_regressors.h"
#include "robot/joint_readings.h"
#include "robot/robot_file.h"

namespace kincal {
namespace {

struct Rows {
  Robot robot;
  std::vector<Eigen::VectorXd> qbar;
};

const Rows& GetRows(const std::string& file) {
  static std::vector<std::pair<std::string, Rows>> cache;
  for (const auto& [name, rows] : cache) {
    if (name == file) return rows;
  }
  Rows rows;
  rows.robot = ReadRobotFile(std::string(KINCAL_SOURCE_DIR) + "/examples/robots/" + file);
  // Non-zero coefficients, so that the chain rule does its full work.
  Rng rng(3);
  Eigen::VectorXd c(rows.robot.joint_errors.num_coefficients());
  for (int k = 0; k < c.size(); ++k) c[k] = rng.Uniform(-1e-3, 1e-3);
  rows.robot.joint_errors.SetCoefficients(c);
  for (int r = 0; r < 1000; ++r) {
    Eigen::VectorXd q(rows.robot.dof());
    for (int j = 0; j < q.size(); ++j) q[j] = rng.Uniform(rows.robot.Limit(j).first, rows.robot.Limit(j).second);
    rows.qbar.push_back(q);
  }
  cache.emplace_back(file, std::move(rows));
  return cache.back().second;
}

template <typename RowFn>
void Measure(benchmark::State& state, const Rows& rows, RowFn row_fn) {
  const JointErrorMap::Want want{true, true, true};
  for (auto _ : state) {
    for (size_t r = 1; r < rows.qbar.size(); ++r) row_fn(rows.qbar[r], &rows.qbar[r - 1], want);
  }
  state.counters["per_row"] = benchmark::Counter(static_cast<double>(rows.qbar.size() - 1),
                                                 benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
  state.counters["coefficients"] = rows.robot.joint_errors.num_coefficients();
}

void BM_RegressorRow_OneByOne(benchmark::State& state, const std::string& file) {
  const Rows& rows = GetRows(file);
  const JointErrorContext context = JointErrorContextOf(rows.robot);
  JointErrorMap map;
  Measure(state, rows, [&](const Eigen::VectorXd& qbar, const Eigen::VectorXd* previous, JointErrorMap::Want want) {
    EvaluateJointErrorMap(rows.robot.joint_errors, context, qbar, previous, want, &map);
    benchmark::DoNotOptimize(map.dq_dparameters.data());
  });
}

void BM_RegressorRow_OnePass(benchmark::State& state, const std::string& file) {
  const Rows& rows = GetRows(file);
  const JointErrorContext context = JointErrorContextOf(rows.robot);
  const PreparedRegressors prepared(rows.robot.joint_errors, rows.robot.model());
  PreparedRegressors::Row scratch;
  JointErrorMap map;
  Measure(state, rows, [&](const Eigen::VectorXd& qbar, const Eigen::VectorXd* previous, JointErrorMap::Want want) {
    prepared.EvaluateMap(rows.robot.joint_errors, context, qbar, previous, want, &scratch, &map);
    benchmark::DoNotOptimize(map.dq_dparameters.data());
  });
}

void Register() {
  for (const char* file : {"ur10_joint_errors.yaml", "irb120_joint_errors.yaml"}) {
    const std::string name(file, std::string(file).find('.'));
    benchmark::RegisterBenchmark(("RegressorRow_OneByOne/" + name).c_str(), BM_RegressorRow_OneByOne, file)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
    benchmark::RegisterBenchmark(("RegressorRow_OnePass/" + name).c_str(), BM_RegressorRow_OnePass, file)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
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
