// scripts/irb120_faro_dataset on the real measurements, against kincal's own reader of the same tables
// (framework/pose_tables.h, an independent implementation in C++): the same rows, values, markers and
// previous poses (the 16 poses reached from a removed one), the even/odd split by pose, and one-line
// errors with exit status 2.
#include <cstdlib>
#include <fstream>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "framework/dataset.h"
#include "framework/pose_tables.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

std::string Faro(const std::string& file) { return SharedDataPath("irb120_faro/" + file); }

#define KINCAL_FARO_DATA_OR_SKIP()                                                                 \
  KINCAL_SKIP_WITHOUT_SHARED_DATA(std::ifstream(Faro("measured_joints.txt")).good(), \
                                  "no ../shared/data/irb120_faro")

int RunConverter(const std::string& arguments, const TempDir& dir, std::string* err) {
  const std::string err_path = dir.path("converter.err");
  const std::string command =
      "'" + SourcePath("scripts/irb120_faro_dataset") + "' " + arguments + " 2>'" + err_path + "'";
  const int status = std::system(command.c_str());
  *err = ReadText(err_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Irb120FaroDataset, SameRowsAndPreviousPosesAsThePoseTablesReader) {
  KINCAL_FARO_DATA_OR_SKIP();
  TempDir dir;
  std::string err;
  ASSERT_EQ(RunConverter("'" + SharedDataPath("irb120_faro") + "' --markers 1,2,3 --split even-odd --out '" +
                             dir.path("faro.csv") + "'",
                         dir, &err),
            0)
      << err;
  const Dataset script = ReadDataset(dir.path("faro.csv"));
  PoseTables tables;
  tables.joints = Faro("processed_joints.txt");
  for (const std::string m : {"1", "2", "3"}) tables.positions.emplace_back("SMR" + m, Faro("processed_SMR_" + m + ".txt"));
  tables.sequence = Faro("measured_joints.txt");
  const Dataset reader = ReadPoseTables(tables, 6);
  ASSERT_EQ(script.rows.size(), reader.rows.size());
  ASSERT_EQ(script.rows.size(), 3u * 982u);
  for (size_t i = 0; i < script.rows.size(); ++i) {
    const Measurement &a = script.rows[i], &b = reader.rows[i];
    EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-15) << i;
    EXPECT_LT((a.p - b.p).cwiseAbs().maxCoeff(), 1e-15) << i;
    EXPECT_EQ(a.marker, b.marker) << i;
    EXPECT_EQ(a.split, (i / 3) % 2 == 0 ? Split::kTrain : Split::kTest) << i;
  }
  const auto previous_script = script.PreviousPoses(), previous_reader = reader.PreviousPoses();
  int from_removed = 0;
  for (size_t i = 0; i < script.rows.size(); ++i) {
    const Eigen::VectorXd* a = script.PreviousQ(previous_script[i]);
    const Eigen::VectorXd* b = reader.PreviousQ(previous_reader[i]);
    ASSERT_EQ(a == nullptr, b == nullptr) << i;
    if (a) {
      EXPECT_LT((*a - *b).cwiseAbs().maxCoeff(), 1e-15) << i;
    }
    if (i % 3 == 0 && previous_script[i].from_columns) ++from_removed;
  }
  EXPECT_EQ(from_removed, 16);  // the data README: 16 kept poses followed a removed one
}

TEST(Irb120FaroDataset, BadInputIsOneLineAndExitTwo) {
  TempDir dir;
  std::string err;
  std::ofstream(dir.path("processed_joints.txt")) << "1 2 3 4 5 6\n1 2 x 4 5 6\n";
  std::ofstream(dir.path("measured_joints.txt")) << "1 2 3 4 5 6\n";
  std::ofstream(dir.path("processed_SMR_1.txt")) << "1 2 3\n4 5 6\n";
  EXPECT_EQ(RunConverter("'" + dir.path("") + "' --out '" + dir.path("out.csv") + "'", dir, &err), 2);
  EXPECT_NE(err.find("processed_joints.txt:2:1: expected 6 numbers"), std::string::npos) << err;
  EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
  EXPECT_FALSE(std::ifstream(dir.path("out.csv")).good());
  // A pose that is not in the sequence.
  std::ofstream(dir.path("processed_joints.txt")) << "1 2 3 4 5 6\n1 2 3 4 5 7\n";
  EXPECT_EQ(RunConverter("'" + dir.path("") + "' --out '" + dir.path("out.csv") + "'", dir, &err), 2);
  EXPECT_NE(err.find("measured_joints.txt:1:1: pose 2 of the joints table is not in this sequence"),
            std::string::npos)
      << err;
  EXPECT_EQ(RunConverter("'" + dir.path("") + "' --markers 4", dir, &err), 2);
  EXPECT_NE(err.find("--markers 4: expected"), std::string::npos) << err;
}

}  // namespace
}  // namespace kincal::testing
