// `kincal plan` end to end: the measurement program of each format, read back by `kincal filter` with
// identified = nominal, changes no byte and its joints are PLAN.csv's to 1e-9 rad; a pool's rows come
// out as written, every column kept, in the planned order; bad input exits 2 with one line naming the
// place, and writes nothing.
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>

#include "framework/csv.h"
#include "framework/units.h"
#include "programs/program.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

const std::string kNominal = SourcePath("examples/robots/ur10_dh.yaml");

// PLAN.csv's joints (q1_deg..q6_deg), rad.
std::vector<Eigen::VectorXd> PlanJoints(const std::string& path) {
  const CsvTable t = ParseCsv(ReadText(path), path);
  std::vector<Eigen::VectorXd> q;
  for (const CsvRow& row : t.rows) {
    Eigen::VectorXd v(6);
    for (int j = 0; j < 6; ++j) v[j] = std::stod(row.cells[FindColumn(t, "q" + std::to_string(j + 1) + "_deg")]) * kDegree;
    q.push_back(v);
  }
  return q;
}

TEST(PlanCommand, ProgramsReadBackByFilterUnchangedWithThePlansJoints) {
  TempDir dir;
  for (const std::string ext : {"mod", "src", "script"}) {
    const std::string plan = dir.path("plan_" + ext + ".csv"), program = dir.path("plan." + ext);
    const auto r = RunKincal("plan --nominal " + kNominal + " --poses 12 --out " + plan + " --program " + program);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto f = RunKincal("filter --nominal " + kNominal + " --identified " + kNominal + " --program " + program +
                             " --out " + dir.path("filtered." + ext));
    ASSERT_EQ(f.exit_code, 0) << f.err;
    EXPECT_NE(f.out.find("0 Cartesian and 12 joint targets; 12 filtered"), std::string::npos) << f.out;
    const std::string text = ReadText(program);
    EXPECT_EQ(ReadText(dir.path("filtered." + ext)), text) << ext;
    const std::vector<ProgramTarget> targets =
        MakeProgramFormat(ProgramFormatFromExtension(program))->Read(text, program);
    const std::vector<Eigen::VectorXd> q = PlanJoints(plan);
    ASSERT_EQ(targets.size(), q.size());
    for (size_t k = 0; k < q.size(); ++k) {
      ASSERT_EQ(targets[k].kind, ProgramTarget::Kind::kJoints);
      EXPECT_LT((targets[k].q - q[k]).cwiseAbs().maxCoeff(), 1e-9) << ext << " pose " << k;
    }
  }
}

TEST(PlanCommand, APoolsRowsComeOutAsWrittenInThePlannedOrder) {
  TempDir dir;
  std::ostringstream pool;
  pool << "# a pool\nid,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_mm,note\n";
  std::vector<std::string> lines;
  for (int i = 0; i < 80; ++i) {
    std::ostringstream line;
    line << "p" << i << "," << 0.05 * i - 2 << "," << -1.2 + 0.011 * i << "," << 1.0 + 0.017 * (i % 7) << ","
         << -1.5 + 0.03 * (i % 11) << "," << 1.5 - 0.02 * (i % 13) << "," << 0.1 * (i % 5) << "," << 1000.5 + i
         << ",n" << i;
    lines.push_back(line.str());
    pool << lines.back() << "\n";
  }
  WriteText(dir.path("pool.csv"), pool.str());
  const auto r = RunKincal("plan --nominal " + kNominal + " --poses 10 --candidates " + dir.path("pool.csv") +
                           " --out " + dir.path("plan.csv") + " --plan-options " + dir.path("o.yaml"));
  // Without the options file: its absence is bad input.
  EXPECT_EQ(r.exit_code, 2);
  WriteText(dir.path("o.yaml"), "{tracker: false, floor_height: -10, criterion: D}\n");
  const auto ok = RunKincal("plan --nominal " + kNominal + " --poses 10 --candidates " + dir.path("pool.csv") +
                            " --out " + dir.path("plan.csv") + " --plan-options " + dir.path("o.yaml"));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  std::istringstream out(ReadText(dir.path("plan.csv")));
  std::string line;
  std::getline(out, line);
  EXPECT_EQ(line, "# a pool");
  std::getline(out, line);
  EXPECT_EQ(line, "id,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_mm,note");
  int rows = 0;
  for (; std::getline(out, line); ++rows) EXPECT_NE(std::find(lines.begin(), lines.end(), line), lines.end()) << line;
  EXPECT_EQ(rows, 10);
}

// `kincal methods --options plan` prints the table the options are read by, defaults included.
TEST(PlanCommand, MethodsPrintThePlansOptions) {
  const auto r = RunKincal("methods --options plan");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* line : {"criterion", "'I'", "acceptance_angle", "tracker_position_m", "settle_time"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
}

TEST(PlanCommand, BadInputExitsTwoWithOneLineAndWritesNothing) {
  TempDir dir;
  WriteText(dir.path("no_q6.csv"), "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg\n1,2,3,4,5\n");
  WriteText(dir.path("word.csv"), "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n1,2,3,4,5,6\n1,2,x,4,5,6\n");
  WriteText(dir.path("bad.yaml"), "acceptance_angle: 30\ncriterion: E\n");
  const std::string base = "plan --nominal " + kNominal + " --out " + dir.path("plan.csv");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + " --poses 5 --candidates " + dir.path("no_q6.csv"), "no_q6.csv:1:1: expected a column q6_deg"},
      {base + " --poses 1 --candidates " + dir.path("word.csv"), "word.csv:3:5: expected a finite number"},
      {base + " --poses 5 --plan-options " + dir.path("bad.yaml"), "bad.yaml: line 2, column 12"},
      {base + " --poses 0", "--poses must be at least 1"},
      {base + " --poses 5000", "candidates meet the constraints"},
      {base + " --poses 5 --program " + dir.path("p.txt"), "no program format for the extension '.txt'"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = RunKincal(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("plan.csv"))) << args;
  }
}

}  // namespace
}  // namespace kincal::testing
