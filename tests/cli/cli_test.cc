// End-to-end tests of the `kincal` program: outputs agree with the library, bad input gives exit status 2
// and one line on stderr naming the file and line, and a failing command leaves existing outputs alone.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "framework/version.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;

std::string Example(const std::string& file) { return SourcePath("examples/robots/" + file); }

int LineCount(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

std::vector<std::string> FilesIn(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

void ExpectFkOutputMatchesLibrary(const std::string& file, const std::string& q_text, const Eigen::VectorXd& q_file) {
  const auto r = RunKincal("fk " + Example(file) + " --q=" + q_text);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  const Robot robot = ReadRobotFile(Example(file));
  Eigen::VectorXd q = q_file * robot.angle_unit.to_si;
  const Eigen::Matrix4d T = robot.model().ForwardKinematics(q).matrix();
  ASSERT_EQ(json["T"].size(), 4u);
  for (int row = 0; row < 4; ++row) {
    ASSERT_EQ(json["T"][row].size(), 4u);
    for (int col = 0; col < 4; ++col) {
      const double expected = (col == 3 && row < 3) ? T(row, col) / robot.length_unit.to_si : T(row, col);
      EXPECT_EQ(json["T"][row][col].get<double>(), expected) << file << " (" << row << ", " << col << ")";
    }
  }
  EXPECT_EQ(json["units"]["length"], robot.length_unit.name);
}

TEST(Cli, FkPrintsTheLibrarysPoseInTheFilesUnits) {
  ExpectFkOutputMatchesLibrary("seed_identified.yaml", "10,20,30,40,50,60",
                               (Eigen::VectorXd(6) << 10, 20, 30, 40, 50, 60).finished());
  ExpectFkOutputMatchesLibrary("ur10_dh.yaml", "0,-90,90,0,90,0.5",
                               (Eigen::VectorXd(6) << 0, -90, 90, 0, 90, 0.5).finished());
  ExpectFkOutputMatchesLibrary("puma560_mdh.yaml", "-12.5,1e1,0,0,0,+3",
                               (Eigen::VectorXd(6) << -12.5, 10, 0, 0, 0, 3).finished());
}

TEST(Cli, FkRejectsAWrongNumberOfJoints) {
  const auto r = RunKincal("fk " + Example("seed_nominal.yaml") + " --q=1,2,3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("expected 6 joint values"), std::string::npos) << r.err;
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
  EXPECT_TRUE(r.out.empty());
}

// The geometric method starts from any convention: the IRB 120 example in Hayati's geometry, swept, is
// identified in Hayati's geometry (converted exactly to modified DH for the construction and back), and
// reproduces the sweeps it was built from. A robot it cannot start from is named, not the dataset.
TEST(Cli, VersionIsTheProjectsVersion) {
  const auto r = RunKincal("--version");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, std::string("kincal ") + KINCAL_VERSION_STRING + "\n");
}

TEST(Cli, HelpNamesTheDatasetColumnsAndTheFixedGroups) {
  const auto r = RunKincal("--help");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Every column the dataset reader knows and every group the error model's `fixed:` holds.
  for (const char* word : {"q1_deg", "x_mm", "qw,qx,qy,qz", "enc1", "sweep", "marker", "session", "split",
                           "from_q1_deg", "base", "tool", "ratios", "markers", "sessions", "joint_<i>",
                           "joint_errors", "gravity", "harmonic", "backlash", "approach"}) {
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
  }
}

TEST(Cli, GeometricIdentifiesAHayatiRobotInItsOwnConvention) {
  testing::TempDir dir;
  // The example's three reflectors sit at the flange, on axis 6: placed apart, each sweep moves them.
  std::string text = testing::ReadText(Example("irb120_joint_errors.yaml"));
  const std::string at_flange = "markers: {SMR1: [0, 0, 0], SMR2: [0, 0, 0], SMR3: [0, 0, 0]}";
  ASSERT_NE(text.find(at_flange), std::string::npos);
  text.replace(text.find(at_flange), at_flange.size(),
               "markers: {SMR1: [60, 40, 30], SMR2: [-50, 30, 20], SMR3: [10, -60, 40]}");
  const std::string robot = dir.path("irb120.yaml"), data = dir.path("sweep.csv");
  testing::WriteText(robot, text);
  ASSERT_EQ(RunKincal("simulate --nominal " + robot + " --truth " + robot + " --protocol sweep --seed 3 --out " + data)
                .exit_code,
            0);
  const auto r = RunKincal("identify --nominal " + robot + " --data " + data + " --method geometric --out " +
                           dir.path("out.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Robot identified = ReadRobotFile(dir.path("out.yaml"));
  EXPECT_EQ(identified.model().convention(), "hayati");
  const Robot start = ReadRobotFile(robot);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(start.dof());
  for (int i = 0; i < q.size(); ++i) q[i] = 0.3 * (i + 1);
  // Noise-free sweeps of the start robot itself: the identified arm is the start arm.
  EXPECT_LT((identified.model().ForwardKinematics(q).matrix() - start.model().ForwardKinematics(q).matrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-9);

  testing::WriteText(dir.path("prismatic.yaml"),
                     "name: p\nconvention: mdh\nunits: {length: mm, angle: deg}\n"
                     "joints:\n  - {alpha: 0, a: 0, theta: 0, d: 0}\n"
                     "  - {alpha: 90, a: 100, theta: 0, d: 0, type: prismatic}\n");
  testing::WriteText(dir.path("two.csv"), "q1_deg,q2_deg,x_mm,y_mm,z_mm,sweep\n0,0,100,0,0,1\n");
  const auto bad = RunKincal("identify --nominal " + dir.path("prismatic.yaml") + " --data " + dir.path("two.csv") +
                             " --method geometric --out " + dir.path("p_out.yaml"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err.rfind("kincal: " + dir.path("prismatic.yaml") + ": ", 0), 0u) << bad.err;
  EXPECT_NE(bad.err.find("prismatic"), std::string::npos) << bad.err;
}

TEST(Cli, SimulateWritesAFileThatReadsBackAsTheLibrarysDataset) {
  testing::TempDir dir;
  const std::string out = dir.path("sweep.csv");
  const auto r = RunKincal("simulate --nominal " + Example("seed_nominal.yaml") + " --truth " +
                           Example("seed_identified.yaml") + " --protocol sweep --noise 10um --seed 7 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Dataset written = ReadDataset(out);
  EXPECT_EQ(DatasetToCsv(written), testing::ReadText(out));
  SimulatorOptions o;
  o.noise_sigma = 10e-6;
  o.seed = 7;
  const Dataset expected = Simulate(testing::SeedNominal(), testing::SeedTruth(), o);
  ASSERT_EQ(written.rows.size(), expected.rows.size());
  ASSERT_EQ(written.rows.size(), 120u);
  for (size_t i = 0; i < expected.rows.size(); ++i) {
    EXPECT_EQ(written.rows[i].encoders, expected.rows[i].encoders);
    EXPECT_EQ(written.rows[i].sweep, expected.rows[i].sweep);
    EXPECT_LT((written.rows[i].q - expected.rows[i].q).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((written.rows[i].p - expected.rows[i].p).cwiseAbs().maxCoeff(), 1e-15);
  }
  // The same command again gives the same bytes.
  const std::string again = dir.path("again.csv");
  ASSERT_EQ(RunKincal("simulate --nominal " + Example("seed_nominal.yaml") + " --truth " +
                      Example("seed_identified.yaml") + " --protocol sweep --noise 10um --seed 7 --out " + again)
                .exit_code,
            0);
  EXPECT_EQ(testing::ReadText(again), testing::ReadText(out));
}

TEST(Cli, BadRobotFileGivesExitTwoAndOneLineNamingFileAndLine) {
  testing::TempDir dir;
  const std::string bad = dir.path("bad_truth.yaml");
  std::string text = testing::ReadText(Example("seed_identified.yaml"));
  text.replace(text.find("counts_per_rev"), std::string("counts_per_rev").size(), "counts_per_turn");
  testing::WriteText(bad, text);
  const auto r = RunKincal("simulate --nominal " + Example("seed_nominal.yaml") + " --truth " + bad +
                           " --protocol random --out " + dir.path("out.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
  // counts_per_rev is on line 16 of seed_identified.yaml, indented by two.
  EXPECT_NE(r.err.find(bad + ":16:3: unknown key 'counts_per_turn'"), std::string::npos) << r.err;
}

TEST(Cli, AFailingCommandLeavesAnExistingOutputUnchanged) {
  testing::TempDir dir;
  const std::string out = dir.path("data.csv");
  const std::string before = "q1_deg,x_mm,y_mm,z_mm\n1,2,3,4\n";
  testing::WriteText(out, before);
  const std::string bad = dir.path("bad.yaml");
  testing::WriteText(bad, "name: bad\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: nan}\n");
  const auto r = RunKincal("simulate --nominal " + Example("seed_nominal.yaml") + " --truth " + bad + " --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad + ":5:"), std::string::npos) << r.err;
  EXPECT_EQ(testing::ReadText(out), before);
  EXPECT_EQ(FilesIn(dir.path("")), (std::vector<std::string>{"bad.yaml", "data.csv"}));  // no temporary left over
}

TEST(Cli, BadDatasetNamesItsLineAndColumn) {
  testing::TempDir dir;
  const std::string data = dir.path("data.csv");
  testing::WriteText(data,
                     "# comment\nq1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm\n0,0,0,0,0,0,1,2,3\n"
                     "0,0,0,0,0,0,1,two,3\n");
  const std::string out = dir.path("identified.yaml");
  const auto r = RunKincal("identify --nominal " + Example("seed_nominal.yaml") + " --data " + data +
                           " --method none --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(data + ":4:15: expected a finite number for y, got 'two'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A pipeline's options file keyed by method names may leave a method out: that method gets its defaults,
// and the listed one its options (here an iteration cap that shows in its stage of the report).
TEST(Cli, PipelineOptionsFileMayOmitAMethod) {
  testing::TempDir dir;
  const std::string data = dir.path("sweep.csv");
  ASSERT_EQ(RunKincal("simulate --nominal " + Example("seed_nominal.yaml") + " --truth " +
                      Example("seed_identified.yaml") + " --protocol sweep --noise 10um --seed 7 --out " + data)
                .exit_code,
            0);
  const std::string options = dir.path("o.yaml");
  testing::WriteText(options, "least_squares: {max_iterations: 1}\n");
  const std::string report = dir.path("report.json");
  const auto r = RunKincal("identify --nominal " + Example("seed_nominal.yaml") + " --data " + data +
                           " --method least_squares,none --options " + options + " --out " +
                           dir.path("identified.yaml") + " --report " + report);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(report));
  ASSERT_EQ(json["stages"].size(), 2u);
  EXPECT_LE(json["stages"][0]["iterations"].get<int>(), 1) << json["stages"][0].dump();
  EXPECT_TRUE(std::filesystem::exists(dir.path("identified.yaml")));
}

TEST(Cli, MissingInputFileIsBadInput) {
  const auto r = RunKincal("fk /nonexistent/robot.yaml --q=0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/robot.yaml"), std::string::npos) << r.err;
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
}

TEST(Cli, UnknownOptionIsBadInput) {
  const auto r = RunKincal("simulate --nominal x --truth y --out z --bogus 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
}

TEST(Cli, HelpAndMethodsExitZero) {
  const auto help = RunKincal("--help");
  EXPECT_EQ(help.exit_code, 0) << help.err;
  for (const char* command : {"fk", "simulate", "identify", "methods"}) {
    EXPECT_NE(help.out.find(command), std::string::npos) << command;
  }
  const auto methods = RunKincal("methods");
  EXPECT_EQ(methods.exit_code, 0) << methods.err;
  for (const char* name : {"mdh", "dh", "none"}) EXPECT_NE(methods.out.find(name), std::string::npos) << name;
  EXPECT_EQ(RunKincal("fk --help").exit_code, 0);
}

// `kincal methods --options NAME` prints the options from the table they are read by: every key with its
// default (least_squares' max_iterations 50, the shared bound_angle_deg 5 deg, loss_scale 1e-4 m).
TEST(Cli, MethodsPrintEachMethodsOptionsWithDefaults) {
  const auto r = RunKincal("methods --options least_squares");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto line_of = [&](const std::string& key) {
    const size_t at = r.out.find("  " + key + " ");
    return at == std::string::npos ? std::string() : r.out.substr(at, r.out.find('\n', at) - at);
  };
  EXPECT_NE(line_of("max_iterations").find(" 50 "), std::string::npos) << r.out;
  EXPECT_NE(line_of("bound_angle_deg").find(" 5 "), std::string::npos) << r.out;
  EXPECT_NE(line_of("loss_scale").find(" 0.0001 m "), std::string::npos) << r.out;
  EXPECT_NE(line_of("fixed").find("list"), std::string::npos) << r.out;
  const auto jacobian = RunKincal("methods --options jacobian");
  EXPECT_NE(jacobian.out.find("random_starts"), std::string::npos) << jacobian.out;
  const auto unknown = RunKincal("methods --options no_such_method");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("no_such_method"), std::string::npos);
}

}  // namespace
}  // namespace kincal
