// Real arms calibrated from distances alone (each arm skips without its data, fails with
// KINCAL_REQUIRE_DATA=1): the training rows of a tracker set turned into each row's distance to one of k
// pivots about 0.7 m from the base (rows shared among them in turn), the pivots' positions not given to
// kincal; the arm fitted to those distances is scored, like the arm fitted to the training points
// themselves, by the distances between the held-out points, which no base or measurement frame changes.
// The arms: the UR10 of ../shared/data/ur10_ipa2021 series B (even rows fit, odd rows scored; three and
// six pivots), on which the distance factor was developed, and the IRB 120 of irb120_faro (reflector
// SMR1, even poses fit, odd scored), on which it was not. Both are held to 1.40 x; the IRB 120 does not
// reach the 1.10 x asked of arms kincal was not developed on (docs/instruments.md has the figures). The
// FANUC sweeps of fanuc_boby2021 are not a case: their 18 training stops of single-joint sweeps give a
// geometry-only point fit hardly better than the nominal arm, and 54 distances a fit worse than it.
// Both fits of an arm: least_squares, max_iterations 200, default priors (`prior: on`: weak parameters stay
// free, drawn to their start), the geometry of the arm's example robot file (joint errors dropped).
// Without priors, the UR10's fit to three pivots holds alpha_5 and tool_z as weak at their start values and
// ends at 0.97 mm training RMS instead of 0.16 mm.
// The pivots are placed once, a priori, around the base the point fit finds (the tracker frame's base
// is only known through a fit): 0.7 m from the base's origin, evenly in turn about its z axis, in its x-y
// plane and 30 deg above it in alternation. Nothing is chosen on the held-out rows.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/estimator.h"
#include "framework/dataset.h"
#include "robot/instrument_scoring.h"
#include "robot/robot_file.h"
#include "tests/real_data/ur10_ipa2021_util.h"

namespace kincal::testing {
namespace {

const char* kOptions = "{max_iterations: 200, prior: on}";

struct Arm {
  const char* name;
  const char* script;      // scripts/...: the converter
  std::string input;       // its input (under ../shared/data)
  const char* arguments;   // the converter's options after the input
  const char* robot;       // examples/robots/...: the nominal geometry (joint errors dropped)
  double bound;            // the distance fit's held-out error at most this times the point fit's
};

// The held-out distance error of the distance fit at most `bound` times the point fit's.
const std::vector<Arm>& Arms() {
  static const std::vector<Arm> arms = {
      {"ur10_ipa2021_B", "scripts/ur10_ipa2021_dataset", Ur10Series(kUr10B), "--split even-odd",
       "examples/robots/ur10_joint_errors.yaml", 1.40},
      {"irb120_faro", "scripts/irb120_faro_dataset", SharedDataPath("irb120_faro"), "--split even-odd",
       "examples/robots/irb120_joint_errors.yaml", 1.40},
  };
  return arms;
}

struct Fits {
  Robot nominal, from_points;
  Dataset all;
  bool available = false;
};

// The arm's data converted and the arm fitted to the training points (cached per arm).
const Fits& PointFit(const Arm& arm) {
  static std::map<std::string, Fits> cache;
  auto it = cache.find(arm.name);
  if (it != cache.end()) return it->second;
  Fits& f = cache[arm.name];
  static TempDir dir;
  if (!std::ifstream(arm.input).good()) return f;
  f.available = true;
  const std::string path = dir.path(std::string(arm.name) + ".csv"), err_path = dir.path("converter.err");
  const std::string command = "'" + SourcePath(arm.script) + "' '" + arm.input + "' " + arm.arguments + " --out '" +
                              path + "' 2>'" + err_path + "'";
  const int status = std::system(command.c_str());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    ADD_FAILURE() << arm.script << " failed: " << ReadText(err_path);
    return f;
  }
  f.all = ReadDataset(path);
  // One tracker placement (a converter may number it session 1): as session 0 the base is the model's own,
  // and fixtures (which live in session 0's frame) can be used.
  for (Measurement& m : f.all.rows) m.session = 0;
  Robot robot = ReadRobotFile(SourcePath(arm.robot));
  robot.joint_errors = JointErrors();
  f.nominal = robot;
  const EstimationReport report = Estimators()
                                      .Create("least_squares", YAML::Load(kOptions))
                                      ->Estimate(f.nominal, f.all.Subset(Split::kTrain), &f.from_points);
  EXPECT_NE(report.status, EstimationStatus::kFailed) << report.BriefReport();
  return f;
}

// k pivots (measurement frame) 0.7 m from the origin of the base of `placed`, at azimuths 360/k deg apart
// about its z axis, in its x-y plane and 30 deg above it in alternation.
std::vector<Eigen::Vector3d> PivotsAbout(const Robot& placed, int k) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < k; ++i) {
    const double azimuth = 2.0 * M_PI * i / k, elevation = (i % 2) * M_PI / 6.0;
    const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                    std::sin(elevation));
    out.push_back(placed.model().base() * (0.7 * direction));
  }
  return out;
}

struct Case {
  size_t arm;
  int pivots;
};

class RealDistances : public ::testing::TestWithParam<Case> {};

TEST_P(RealDistances, DistancesAlonePredictHeldOutDistancesAlmostAsWellAsPoints) {
  const Arm& arm = Arms()[GetParam().arm];
  const int k = GetParam().pivots;
  KINCAL_SKIP_WITHOUT_SHARED_DATA(std::ifstream(arm.input).good(), "no " << arm.input);
  const Fits& f = PointFit(arm);
  ASSERT_FALSE(f.all.rows.empty());
  std::vector<std::string> names;
  for (int i = 0; i < k; ++i) names.push_back("P" + std::to_string(i + 1));
  const Dataset distances = DistancesFromPoints(f.all.Subset(Split::kTrain), PivotsAbout(f.from_points, k), names);
  Robot from_distances;
  const EstimationReport report = Estimators()
                                      .Create("least_squares", YAML::Load(kOptions))
                                      ->Estimate(f.nominal, distances, &from_distances);
  EXPECT_NE(report.status, EstimationStatus::kFailed) << report.BriefReport();
  const Dataset test = f.all.Subset(Split::kTest);
  const ErrorStats nominal = PairwiseDistanceErrors(f.nominal, f.nominal, test);
  const ErrorStats points = PairwiseDistanceErrors(f.nominal, f.from_points, test);
  const ErrorStats dist = PairwiseDistanceErrors(f.nominal, from_distances, test);
  std::printf("%s, %d pivots: held-out distance errors RMS nominal %.4f mm, point fit %.4f mm, distance fit "
              "%.4f mm (ratio %.3f; %s)\n",
              arm.name, k, nominal.rms * 1e3, points.rms * 1e3, dist.rms * 1e3, dist.rms / points.rms,
              report.BriefReport().c_str());
  EXPECT_LT(points.rms, 0.5 * nominal.rms);
  EXPECT_LE(dist.rms, arm.bound * points.rms);
}

INSTANTIATE_TEST_SUITE_P(Arms, RealDistances,
                         ::testing::Values(Case{0, 3}, Case{0, 6}, Case{1, 3}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(Arms()[info.param.arm].name) + "_" +
                                  std::to_string(info.param.pivots) + "_pivots";
                         });

}  // namespace
}  // namespace kincal::testing
