// Replays files through a fuzz harness without libFuzzer: kincal_fuzz_replay HARNESS FILE_OR_FOLDER...
// ctest runs it on fuzz/regressions/<harness>/ (every input that ever crashed) and on the seed corpus.
// A finding aborts (exit status from SIGABRT), which fails the test.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/harnesses.h"

namespace {

struct NamedHarness {
  const char* name;
  int (*run)(const uint8_t* data, size_t size);
};
const NamedHarness kHarnesses[] = {{"robot_file", kincal::fuzz::FuzzRobotFile},
                                   {"dataset", kincal::fuzz::FuzzDataset},
                                   {"targets", kincal::fuzz::FuzzTargets},
                                   {"study_file", kincal::fuzz::FuzzStudyFile},
                                   {"options", kincal::fuzz::FuzzOptions},
                                   {"pipeline", kincal::fuzz::FuzzPipeline},
                                   {"urdf", kincal::fuzz::FuzzUrdf},
                                   {"programs", kincal::fuzz::FuzzPrograms}};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: kincal_fuzz_replay HARNESS FILE_OR_FOLDER...\n");
    return 2;
  }
  int (*harness)(const uint8_t*, size_t) = nullptr;
  for (const NamedHarness& h : kHarnesses) {
    if (std::string(argv[1]) == h.name) harness = h.run;
  }
  if (!harness) {
    std::fprintf(stderr, "unknown harness '%s'\n", argv[1]);
    return 2;
  }
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (int i = 2; i < argc; ++i) {
    if (fs::is_directory(argv[i])) {
      for (const auto& entry : fs::directory_iterator(argv[i])) {
        if (entry.is_regular_file()) files.push_back(entry.path());
      }
    } else if (fs::is_regular_file(argv[i])) {
      files.push_back(argv[i]);
    }
  }
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::fprintf(stderr, "%s\n", file.c_str());
    harness(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("%zu files replayed through %s\n", files.size(), argv[1]);
  return 0;
}
