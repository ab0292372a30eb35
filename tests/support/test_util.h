#pragma once
// Shared test helpers: example robots, central differences, temporary folders, running the CLI.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

#include <Eigen/Core>

#include "robot/robot.h"
#include "robot/robot_file.h"

namespace kincal::testing {

inline std::string SourcePath(const std::string& relative) { return std::string(KINCAL_SOURCE_DIR) + "/" + relative; }
inline std::string SharedDataPath(const std::string& relative) {
  return std::string(KINCAL_SHARED_DATA_DIR) + "/" + relative;
}
inline Robot LoadExampleRobot(const std::string& file) { return ReadRobotFile(SourcePath("examples/robots/" + file)); }
inline Robot SeedNominal() { return LoadExampleRobot("seed_nominal.yaml"); }
inline Robot SeedTruth() { return LoadExampleRobot("seed_identified.yaml"); }

// Central difference of a vector function f: R^n -> R^m at x with step h: (f(x + h e_i) - f(x - h e_i)) / 2h.
inline Eigen::MatrixXd CentralDifference(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                         const Eigen::VectorXd& x, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
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

std::string ReadText(const std::string& path);
void WriteText(const std::string& path, const std::string& text);

}  // namespace kincal::testing
