// Datasets of 10^6 and 10^7 rows: the first is read, predicted and written; the second, on a
// machine with less memory than it needs, is refused with a message that says so (exit status 2)
// instead of being ended by the kernel's out-of-memory killer. The machine is emulated with
// KINCAL_MEMORY_LIMIT_MB so that the test means the same everywhere. Labelled slow.
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::TempDir;

void WriteRows(const std::string& path, long rows) {
  std::ofstream out(path, std::ios::binary);
  out << "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm\n";
  std::string line;
  for (long i = 0; i < rows; ++i) {
    line = std::to_string(i % 90) + ",1,2,3,4,5,375.5,30,537\n";
    out << line;
  }
}

class MemoryLimit {
 public:
  explicit MemoryLimit(const char* mb) { ::setenv("KINCAL_MEMORY_LIMIT_MB", mb, 1); }
  ~MemoryLimit() { ::unsetenv("KINCAL_MEMORY_LIMIT_MB"); }
};

TEST(BigData, AMillionRowsAreReadPredictedAndWritten) {
  TempDir dir;
  WriteRows(dir.path("big.csv"), 1000000);
  MemoryLimit limit("3000");  // a small machine still reads a million rows
  const auto r = RunKincal("predict --robot " + testing::SourcePath("examples/robots/seed_nominal.yaml") + " --data " +
                           dir.path("big.csv") + " --out " + dir.path("pred.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir.path("pred.csv"));
  long lines = 0;
  std::string line;
  while (std::getline(in, line)) lines += line.empty() || line[0] != '#';  // '#' lines: provenance comments
  EXPECT_EQ(lines, 1000001);                                               // the header and one row per dataset row
}

TEST(BigData, TenMillionRowsBeyondTheMemoryAreRefusedWithAMessage) {
  TempDir dir;
  WriteRows(dir.path("huge.csv"), 10000000);
  MemoryLimit limit("3000");
  const auto r = RunKincal("identify --nominal " + testing::SourcePath("examples/robots/seed_nominal.yaml") +
                           " --data " + dir.path("huge.csv") + " --method least_squares --out " + dir.path("out.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("kincal: " + dir.path("huge.csv") + ": reading 10000001 lines needs about", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("GB available"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("out.yaml")));
}

}  // namespace
}  // namespace kincal
