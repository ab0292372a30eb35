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

#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

using namespace kincal;

namespace {

struct Protocol {
  const char* name;
  int stops;
  double step_deg;
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
    if (arg == "--seeds" && i + 1 < argc)
      seeds = std::atoi(argv[++i]);
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
  std::printf(
      "identification: geometric,ratio_regression; mean over %d seeds of each run's mean held-out error, mm, "
      "+- its standard error; in brackets the mean paired difference to the geometric fit on the same data\n\n",
      seeds);

  const std::vector<Protocol> protocols = {{"20 x 2 deg", 20, 2.0}, {"20 x 6 deg", 20, 6.0}, {"36 x 10 deg", 36, 10.0}};
  const std::vector<double> noises = {0.01e-3, 0.1e-3};
  const std::vector<std::string> fits = {"kasa", "pratt", "taubin", "geometric"};
  std::printf("%-12s %-8s", "protocol", "noise");
  for (const auto& f : fits) std::printf(" %-36s", f.c_str());
  std::printf("\n%-21s", "");
  for (size_t f = 0; f < fits.size(); ++f)
    std::printf(" %-36s", f + 1 < fits.size() ? "mean +- s.e. [paired vs geom.]" : "mean +- s.e.");
  std::printf("\n");
  for (const Protocol& protocol : protocols) {
    for (double noise : noises) {
      std::printf("%-12s %-8s", protocol.name, (std::to_string(noise * 1e3).substr(0, 4) + " mm").c_str());
      // errors[f][s]: NaN where the run was refused.
      std::vector<std::vector<double>> errors(fits.size(), std::vector<double>(seeds, NAN));
      std::vector<int> failures(fits.size(), 0);
      for (size_t f = 0; f < fits.size(); ++f) {
        YAML::Node options;
        options["circle_fit"] = fits[f];
        options["stddev"] = "none";
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
            ++failures[f];
            continue;
          }
          errors[f][s - 1] = EvaluatePredictions(nominal, identified, test).position_stats.mean;
        }
      }
      const std::vector<double>& reference = errors.back();
      for (size_t f = 0; f < fits.size(); ++f) {
        std::vector<double> valid, paired;
        for (int s = 0; s < seeds; ++s) {
          if (std::isnan(errors[f][s])) continue;
          valid.push_back(errors[f][s]);
          if (!std::isnan(reference[s])) paired.push_back(errors[f][s] - reference[s]);
        }
        char text[96];
        int used = std::snprintf(text, sizeof(text), "%.4f +- %.4f", Mean(valid) * 1e3, StdErr(valid) * 1e3);
        if (f + 1 < fits.size()) {
          used += std::snprintf(text + used, sizeof(text) - used, " [%+.4f +- %.4f]", Mean(paired) * 1e3,
                                StdErr(paired) * 1e3);
        }
        if (failures[f]) std::snprintf(text + used, sizeof(text) - used, " (%d refused)", failures[f]);
        std::printf(" %-36s", text);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  return 0;
}
