// The seed's identification in simulation (METHOD.md 2 and 3): sweep each joint of the seed's arm 20 x
// 2 deg from the calibration configuration, fit each joint's axis from its marker's arc (circle point
// analysis), build MDH frames by common normals, then regress each joint's reduction ratio on its encoder
// counts. The truth is the arm as the paper identified it (Table 2, Table 3's identified ratios); the
// controller knows only the nominal (Table 1, nominal ratios). Run: ./build/examples/kincal_seed_geometric
#include <cstdio>
#include <string>

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

using namespace kincal;

namespace {

constexpr double kMm = 1e3, kDeg = 180.0 / M_PI;

void PrintTables(const Robot& nominal, const Robot& truth, const Robot& identified) {
  std::printf("    | %-29s| %-29s| %-29s| %-29s\n", "alpha (deg)", "a (mm)", "theta (deg)", "d (mm)");
  std::printf("  i |");
  for (int k = 0; k < 4; ++k) std::printf("  Table 1    truth    found  |");
  std::printf("\n");
  for (int i = 1; i <= nominal.dof(); ++i) {
    std::printf("  %d |", i);
    for (const char* key : {"alpha", "a", "theta", "d"}) {
      const std::string name = std::string(key) + "_" + std::to_string(i);
      const double scale = (name[0] == 'a' && name[1] == '_') || key[0] == 'd' ? kMm : kDeg;
      std::printf("  %8.2f %8.3f %8.3f  |", nominal.model().Parameter(name) * scale,
                  truth.model().Parameter(name) * scale, identified.model().Parameter(name) * scale);
    }
    std::printf("\n");
  }
  const Eigen::Vector3d base = identified.model().base().translation() * kMm;
  const Eigen::Vector3d tool = identified.model().tool().translation() * kMm;
  std::printf(
      "  base xyz found (mm): %.3f %.3f %.3f (truth 0 0 0); tool xyz found (mm): %.3f %.3f %.3f (truth 40 30 100)\n",
      base.x(), base.y(), base.z(), tool.x(), tool.y(), tool.z());
  std::printf("  ratio K | nominal   truth     found\n");
  for (int i = 0; i < nominal.dof(); ++i) {
    std::printf("  joint %d | %8.2f %8.2f %8.2f\n", i + 1, nominal.drives->ratio[i], truth.drives->ratio[i],
                identified.drives->ratio[i]);
  }
}

}  // namespace

int main() {
  const std::string robots = std::string(KINCAL_SOURCE_DIR) + "/examples/robots/";
  const Robot nominal = ReadRobotFile(robots + "seed_nominal.yaml");
  const Robot truth = ReadRobotFile(robots + "seed_identified.yaml");

  // 300 random poses, noise-free, to score each identified robot on poses it never saw.
  SimulatorOptions random;
  random.protocol = "random";
  random.poses = 300;
  random.seed = 7;
  const Dataset held_out = Simulate(nominal, truth, random);
  std::printf("nominal robot: mean error on 300 held-out poses %.3f mm\n\n",
              EvaluatePredictions(nominal, nominal, held_out).position_stats.mean * kMm);

  struct Noise {
    const char* name;
    double sigma, per_metre;
  };
  for (const Noise& noise : {Noise{"no noise", 0.0, 0.0}, Noise{"laser tracker, 5 um + 5 um/m per axis", 5e-6, 5e-6}}) {
    SimulatorOptions sweeps;  // the seed's protocol: joints 6..1, 20 stops 2 deg apart, from q = 0
    sweeps.noise_sigma = noise.sigma;
    sweeps.noise_range_coefficient = noise.per_metre;
    sweeps.seed = 1;
    const Dataset data = Simulate(nominal, truth, sweeps);

    Robot identified;
    const std::vector<EstimationReport> reports =
        RunPipeline({"geometric", "ratio_regression"}, {YAML::Node(), YAML::Node()}, nominal, data, &identified);
    std::printf("== %s: %zu stops ==\n", noise.name, data.rows.size());
    for (const auto& r : reports) std::printf("  %s\n", r.BriefReport().c_str());
    PrintTables(nominal, truth, identified);
    // One standard deviation of a few parameters, as the geometric stage propagated it from the noise.
    for (const auto& p : reports[0].parameters) {
      if (p.name == "a_2" || p.name == "d_3" || p.name == "alpha_6") {
        std::printf("  %s: +- %.4f %s\n", p.name.c_str(), p.stddev * (p.unit == "m" ? kMm : kDeg),
                    p.unit == "m" ? "mm" : "deg");
      }
    }
    std::printf("  identified robot: mean error on the held-out poses %.4f mm\n\n",
                EvaluatePredictions(nominal, identified, held_out).position_stats.mean * kMm);
  }
  return 0;
}
