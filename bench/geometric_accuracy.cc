// How accurate is the seed's identification (geometric + ratio_regression) in simulation? For the seed's
// arm (truth: examples/robots/seed_identified.yaml, nominal: seed_nominal.yaml), every circle fit, two
// noise levels and three sweep protocols, it prints the mean position error in predicting 300 held-out
// random poses (noise-free truth, so the figure is the model's error alone), averaged over seeds.
//
//   ./build/bench/kincal_geometric_accuracy [--seeds 20]
//
// Not a Google Benchmark: it measures accuracy, not speed. The numbers chose the geometric estimator's
// default circle fit (circle_fit.h).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/estimator.h"
#include "framework/prediction.h"
#include "framework/robot_file.h"
#include "framework/simulator.h"

using namespace kincal;

namespace {

struct Protocol {
  const char* name;
  int stops;
  double step_deg;
};

struct Cell {
  std::vector<double> errors;  // per seed: mean held-out error, m
  int failures = 0;
};

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

double StdErr(const std::vector<double>& v) {
  if (v.size() < 2) return NAN;
  const double m = Mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / (v.size() - 1) / v.size());
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 20;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--seeds" && i + 1 < argc) seeds = std::atoi(argv[++i]);
    else {
      std::fprintf(stderr, "usage: %s [--seeds N]\n", argv[0]);
      return 2;
    }
  }
  const std::string robots = std::string(KINCAL_SOURCE_DIR) + "/examples/robots/";
  const Robot nominal = ReadRobotFile(robots + "seed_nominal.yaml");
  const Robot truth = ReadRobotFile(robots + "seed_identified.yaml");

  SimulatorOptions held_out;
  held_out.protocol = "random";
  held_out.poses = 300;
  held_out.seed = 20240601;
  const Dataset test = Simulate(nominal, truth, held_out);
  std::printf("held-out: 300 random poses within the nominal limits, noise-free; nominal robot's mean error %.4f mm\n",
              EvaluatePredictions(nominal, nominal, test).position_stats.mean * 1e3);
  std::printf("identification: geometric,ratio_regression; mean over %d seeds of each run's mean held-out error, mm "
              "(+- standard error); failures = runs refused as degenerate\n\n", seeds);

  const std::vector<Protocol> protocols = {{"20 x 2 deg", 20, 2.0}, {"20 x 6 deg", 20, 6.0}, {"36 x 10 deg", 36, 10.0}};
  const std::vector<double> noises = {0.01e-3, 0.1e-3};
  const std::vector<std::string> fits = {"kasa", "pratt", "taubin", "geometric"};
  std::printf("%-12s %-9s", "protocol", "noise");
  for (const auto& f : fits) std::printf(" %-22s", f.c_str());
  std::printf("\n");
  for (const Protocol& protocol : protocols) {
    for (double noise : noises) {
      std::printf("%-12s %-9s", protocol.name, (std::to_string(noise * 1e3).substr(0, 4) + " mm").c_str());
      for (const std::string& fit : fits) {
        YAML::Node options;
        options["circle_fit"] = fit;
        options["stddev"] = "none";
        Cell cell;
        for (int s = 1; s <= seeds; ++s) {
          SimulatorOptions o;
          o.stops = protocol.stops;
          o.step = protocol.step_deg * M_PI / 180.0;
          o.noise_sigma = noise;
          o.seed = static_cast<uint64_t>(s);
          const Dataset data = Simulate(nominal, truth, o);
          Robot identified;
          try {
            RunPipeline({"geometric", "ratio_regression"}, {options, options}, nominal, data, &identified);
          } catch (const std::invalid_argument&) {
            ++cell.failures;
            continue;
          }
          cell.errors.push_back(EvaluatePredictions(nominal, identified, test).position_stats.mean);
        }
        char text[64];
        std::snprintf(text, sizeof(text), "%.4f +- %.4f%s", Mean(cell.errors) * 1e3, StdErr(cell.errors) * 1e3,
                      cell.failures ? (" (" + std::to_string(cell.failures) + "f)").c_str() : "");
        std::printf(" %-22s", text);
        std::fflush(stdout);
      }
      std::printf("\n");
    }
  }
  return 0;
}
