// framework/atomic_file: the promise about outputs (docs/RELIABILITY.md). A written file is complete
// after the rename; a failure leaves the previous file unchanged and no temporary file behind. (That the
// data reaches the disk before the rename, fsync, cannot be observed without cutting the power; the
// test checks what can be: the content, the folder, the error paths.)
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

namespace fs = std::filesystem;
using testing::ReadText;
using testing::TempDir;
using testing::WriteText;

int EntriesIn(const std::string& folder) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    (void)entry;
    ++n;
  }
  return n;
}

TEST(AtomicFile, LargeContentIsCompleteAfterTheRenameAndNoTemporaryRemains) {
  TempDir dir;
  std::string content;
  for (int i = 0; i < 200000; ++i) content += std::to_string(i) + ",0.125,-3e-7\n";  // ~3.6 MB
  WriteFileAtomically(dir.path("out.csv"), content);
  EXPECT_EQ(ReadText(dir.path("out.csv")), content);
  EXPECT_EQ(EntriesIn(dir.path("")), 1);
}

TEST(AtomicFile, ReplacesAnExistingFileWhole) {
  TempDir dir;
  WriteText(dir.path("out.yaml"), std::string(10000, 'x'));
  WriteFileAtomically(dir.path("out.yaml"), "short\n");
  EXPECT_EQ(ReadText(dir.path("out.yaml")), "short\n");
  EXPECT_EQ(EntriesIn(dir.path("")), 1);
}

TEST(AtomicFile, AWriterThatThrowsLeavesThePreviousFileAndNoTemporary) {
  TempDir dir;
  WriteText(dir.path("out.csv"), "previous\n");
  EXPECT_THROW(WriteFileAtomically(dir.path("out.csv"),
                                   [](std::ostream& out) {
                                     out << std::string(100000, 'y');
                                     throw std::runtime_error("interrupted half way");
                                   }),
               std::runtime_error);
  EXPECT_EQ(ReadText(dir.path("out.csv")), "previous\n");
  EXPECT_EQ(EntriesIn(dir.path("")), 1);
}

TEST(AtomicFile, AFailedRenameLeavesNoTemporaryAndSaysWhichFile) {
  TempDir dir;
  // A non-empty folder where the file should go: the rename fails after the temporary was written.
  fs::create_directory(dir.path("out.csv"));
  WriteText(dir.path("out.csv/keep"), "x");
  try {
    WriteFileAtomically(dir.path("out.csv"), "content\n");
    FAIL() << "expected an error";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.path("out.csv"), 0), 0u) << e.what();
  }
  EXPECT_EQ(EntriesIn(dir.path("")), 1);
  EXPECT_TRUE(fs::is_directory(dir.path("out.csv")));
}

TEST(AtomicFile, AMissingFolderIsBadInputNamingThePath) {
  TempDir dir;
  try {
    WriteFileAtomically(dir.path("no/such/folder/out.csv"), "content\n");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, AFullDiskIsReportedAndLeavesNoTemporary) {
  // The temporary file's name is fixed (".NAME.tmpPID"): made a link to /dev/full, which fails every
  // write with ENOSPC, it lets the test see what a full disk does to the writer.
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  TempDir dir;
  WriteText(dir.path("out.csv"), "previous\n");
  fs::create_symlink("/dev/full", dir.path(".out.csv.tmp" + std::to_string(::getpid())));
  try {
    WriteFileAtomically(dir.path("out.csv"), std::string(1 << 20, 'z'));
    FAIL() << "expected an error";
  } catch (const IoError& e) {
    // The file, what failed and the system's reason (ENOSPC).
    EXPECT_EQ(std::string(e.what()).rfind(dir.path("out.csv") + ": write failed: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::strerror(ENOSPC)), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadText(dir.path("out.csv")), "previous\n");
  EXPECT_EQ(EntriesIn(dir.path("")), 1);
}

}  // namespace
}  // namespace kincal
