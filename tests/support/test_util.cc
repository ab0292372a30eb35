#include "tests/support/test_util.h"

#include <fstream>
#include <random>
#include <sstream>

#include <sys/wait.h>
#include <unistd.h>

#include "framework/random.h"

namespace kincal::testing {

TempDir::TempDir() {
  static int counter = 0;
  dir_ = std::filesystem::temp_directory_path() /
         ("kincal_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::unique_ptr<KinematicModel> RandomizedModel(std::unique_ptr<KinematicModel> model, uint64_t seed) {
  Rng rng(seed);
  Eigen::VectorXd p = model->Parameters();
  for (int i = 0; i < p.size(); ++i) {
    const bool angle = model->parameter_info()[i].kind == ParameterInfo::Kind::kAngle;
    p[i] = angle ? rng.Uniform(-1.5, 1.5) : rng.Uniform(-0.5, 0.5);
  }
  model->SetParameters(p);
  return model;
}

CommandResult RunKincal(const std::string& arguments) {
  TempDir tmp;
  const std::string out = tmp.path("stdout"), err = tmp.path("stderr");
  const std::string command = std::string(KINCAL_CLI) + " " + arguments + " >" + out + " 2>" + err + " </dev/null";
  const int status = std::system(command.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadText(out);
  r.err = ReadText(err);
  return r;
}

}  // namespace kincal::testing
