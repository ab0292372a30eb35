#pragma once
// The ur10_ipa2021 measurements (../shared/data/ur10_ipa2021) through scripts/ur10_ipa2021_dataset, for
// the real-data tests: where the data are, running the converter, and reading a source row independently.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "tests/support/test_util.h"

namespace kincal::testing {

inline std::string Ur10Series(const std::string& file) { return SharedDataPath("ur10_ipa2021/" + file); }
inline const char* kUr10A = "Series_A/measurements_grid.csv";
inline const char* kUr10B = "Series_B/measurements_joint_configurations.csv";
inline const char* kUr10C = "Series_C/measurements_random_poses.csv";
inline const char* kUr10D = "Series_D/measurements_iso_cubes.csv";

// True when the data are here; without them a test skips (fails under KINCAL_REQUIRE_DATA=1).
inline bool HaveUr10Data() { return std::ifstream(Ur10Series(kUr10D)).good(); }
// (tests/support/test_util.h's KINCAL_SKIP_WITHOUT_SHARED_DATA: the skip, or the failure.)
#define KINCAL_UR10_DATA_OR_SKIP() \
  KINCAL_SKIP_WITHOUT_SHARED_DATA(::kincal::testing::HaveUr10Data(), "no ../shared/data/ur10_ipa2021")

// Runs scripts/ur10_ipa2021_dataset with `arguments` (shell-quoted); stderr into *err.
inline int RunUr10Converter(const std::string& arguments, const TempDir& dir, std::string* err) {
  const std::string err_path = dir.path("converter.err");
  const std::string command =
      "'" + SourcePath("scripts/ur10_ipa2021_dataset") + "' " + arguments + " 2>'" + err_path + "'";
  const int status = std::system(command.c_str());
  if (err) *err = ReadText(err_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Data row `row` (0-based, after the header) of a source file: its ';'-separated cells with '.' decimals,
// keyed by the header's names.
inline std::vector<std::pair<std::string, std::string>> Ur10SourceRow(const std::string& path, int row) {
  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  for (int i = 0; i <= row; ++i) std::getline(in, line);
  const auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::stringstream ss(text);
    for (std::string cell; std::getline(ss, cell, ';');) cells.push_back(cell);
    return cells;
  };
  const std::vector<std::string> names = split(header), cells = split(line);
  std::vector<std::pair<std::string, std::string>> out;
  for (size_t i = 0; i < names.size() && i < cells.size(); ++i) {
    std::string v = cells[i];
    for (char& c : v) c = c == ',' ? '.' : c;
    out.emplace_back(names[i], v);
  }
  return out;
}

inline double Ur10SourceValue(const std::vector<std::pair<std::string, std::string>>& row, const std::string& name) {
  for (const auto& [k, v] : row) {
    if (k == name) return std::stod(v);
  }
  return NAN;
}

}  // namespace kincal::testing
