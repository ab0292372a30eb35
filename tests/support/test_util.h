#pragma once
// Shared test helpers: example robots, temporary folders, running the CLI (central differences: the
// installed model conformance kit, testing/model_conformance.h).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "framework/random.h"
#include "robot/robot.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "testing/model_conformance.h"  // CentralDifference, RandomJoints

namespace kincal::testing {

inline std::string SourcePath(const std::string& relative) { return std::string(KINCAL_SOURCE_DIR) + "/" + relative; }
inline std::string SharedDataPath(const std::string& relative) {
  return std::string(KINCAL_SHARED_DATA_DIR) + "/" + relative;
}

// Whether the real-data tests must run: KINCAL_REQUIRE_DATA=1 in the environment (scripts/test sets it
// when ../shared/data exists) turns their skip into a failure, so that a moved or unreadable data folder
// cannot pass unseen as a run of skips.
inline bool SharedDataRequired() {
  const char* value = std::getenv("KINCAL_REQUIRE_DATA");
  return value != nullptr && std::string(value) == "1";
}

// In a test body or SetUp (GoogleTest included): when `available` is false, skips the test with `message`,
// or fails it under KINCAL_REQUIRE_DATA=1. Either way the function returns.
#define KINCAL_SKIP_WITHOUT_SHARED_DATA(available, message) \
  do {                                                      \
    if (!(available)) {                                     \
      if (::kincal::testing::SharedDataRequired()) {        \
        FAIL() << "KINCAL_REQUIRE_DATA=1, but " << message; \
      } else {                                              \
        GTEST_SKIP() << message;                            \
      }                                                     \
    }                                                       \
  } while (0)

inline Robot LoadExampleRobot(const std::string& file) { return ReadRobotFile(SourcePath("examples/robots/" + file)); }
inline Robot SeedNominal() { return LoadExampleRobot("seed_nominal.yaml"); }
inline Robot SeedTruth() { return LoadExampleRobot("seed_identified.yaml"); }

// `poses` random configurations within the joint limits, measured noise-free on `truth` and read back by
// `controller` (robot/simulator.h's "random" protocol).
inline Dataset RandomPoses(const Robot& controller, const Robot& truth, int poses, uint64_t seed = 1) {
  SimulatorOptions so;
  so.protocol = "random";
  so.poses = poses;
  so.seed = seed;
  return Simulate(controller, truth, so);
}

// `data` with Gaussian noise of `sigma` (m per axis) added to every row's position, drawn from Rng(seed).
inline Dataset WithPositionNoise(Dataset data, double sigma, uint64_t seed) {
  Rng rng(seed);
  for (auto& m : data.rows) m.p += sigma * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
  return data;
}

// A fresh empty folder under the system temp dir, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  std::filesystem::path dir_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs the kincal binary with arguments (a shell-quoted string).
CommandResult RunKincal(const std::string& arguments);

// `model` with random but reproducible parameters (angles in [-1.5, 1.5] rad, lengths in [-0.5, 0.5] m;
// geometry, base and tool), so that no derivative is tested at a special value.
std::unique_ptr<KinematicModel> RandomizedModel(std::unique_ptr<KinematicModel> model, uint64_t seed);

std::string ReadText(const std::string& path);
void WriteText(const std::string& path, const std::string& text);

}  // namespace kincal::testing
