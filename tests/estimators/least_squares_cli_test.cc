// `kincal identify --method least_squares` end to end: held-out validation from a second file or from a
// `split` column, and bad input (too few poses, NaN, wrong joint count): exit status 2, a one-line reason,
// nothing written.
#include <algorithm>
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "framework/dataset.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

const std::string kNominal = SourcePath("examples/robots/seed_nominal.yaml");
const std::string kTruth = SourcePath("examples/robots/seed_identified.yaml");

std::string Simulate(const TempDir& tmp, const std::string& name, int poses, int seed) {
  const std::string path = tmp.path(name);
  const CommandResult r =
      RunKincal("simulate --nominal " + kNominal + " --truth " + kTruth + " --protocol random --poses " +
                std::to_string(poses) + " --noise 10um --seed " + std::to_string(seed) + " --out " + path);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return path;
}

// Every joint-level term of the UR10 file, without priors, fitted on small sweeps (1.5 deg steps) of an arm
// that has none: the terms fit the noise and extrapolate metres-wide to random poses. identify fits geometry
// alone on the same rows, and the model, far worse than it on the held-out rows, is not `ok`.
TEST(LeastSquaresCli, FlagsAModelThatPredictsWorseThanGeometryAlone) {
  TempDir tmp;
  const std::string robot = SourcePath("examples/robots/ur10_joint_errors.yaml");
  const auto simulate = [&](const std::string& name, const std::string& protocol) {
    const CommandResult r = RunKincal("simulate --nominal " + robot + " --truth " + robot + " " + protocol +
                                      " --noise 50um --out " + tmp.path(name));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  simulate("train.csv", "--protocol sweep --stops 12 --step 1.5 --seed 1");
  simulate("test.csv", "--protocol random --poses 200 --seed 2");
  WriteText(tmp.path("options.yaml"), "prior: off\nmax_iterations: 100\n");
  const CommandResult r = RunKincal("identify --nominal " + robot + " --data " + tmp.path("train.csv") +
                                    " --method least_squares --options " + tmp.path("options.yaml") + " --validate " +
                                    tmp.path("test.csv") + " --out " + tmp.path("id.yaml") + " --report " +
                                    tmp.path("report.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("heldout_worse_than_geometry"), std::string::npos) << r.err;
  const nlohmann::json v = nlohmann::json::parse(ReadText(tmp.path("report.json")))["validation"];
  EXPECT_EQ(v["status"], "heldout_worse_than_geometry");
  EXPECT_GT(v["identified"]["rms"].get<double>(), 1.5 * v["geometry"]["rms"].get<double>());
  EXPECT_LT(v["geometry"]["rms"].get<double>(), 1.0);  // mm: geometry alone extrapolates fine
}

TEST(LeastSquaresCli, ValidatesOnAHeldOutFile) {
  TempDir tmp;
  const std::string train = Simulate(tmp, "train.csv", 80, 1);
  const std::string test = Simulate(tmp, "test.csv", 100, 2);
  const CommandResult r =
      RunKincal("identify --nominal " + kNominal + " --data " + train + " --method least_squares --validate " + test +
                " --out " + tmp.path("id.yaml") + " --report " + tmp.path("report.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("least_squares: converged"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("held-out (100 rows)"), std::string::npos) << r.out;
  const nlohmann::json report = nlohmann::json::parse(ReadText(tmp.path("report.json")));
  EXPECT_LT(report["validation"]["identified"]["rms"].get<double>(), 0.05);  // mm; 10 um noise
  EXPECT_EQ(report["validation"]["status"], "ok");
  EXPECT_GT(report["validation"]["nominal"]["rms"].get<double>(), 1.0);
  const auto& stage = report["stages"][0];
  EXPECT_EQ(stage["fixed_parameters"].size(), 6u);
  int with_stddev = 0;
  for (const auto& p : stage["parameters"]) with_stddev += p["free"].get<bool>() && p["stddev"].is_number();
  EXPECT_EQ(with_stddev, 33);
  for (const char* key : {"O1", "O2", "O3", "O4", "O5"})
    EXPECT_GT(stage["details"]["observability"][key].get<double>(), 0.0);
  const Robot identified = ReadRobotFile(tmp.path("id.yaml"));
  EXPECT_NEAR(identified.drives->ratio[2], 4815.60, 1.0);
}

TEST(LeastSquaresCli, ValidatesOnTheTestRowsOfASplitColumn) {
  TempDir tmp;
  Dataset data = ReadDataset(Simulate(tmp, "all.csv", 120, 3));
  for (size_t i = 0; i < data.rows.size(); ++i) data.rows[i].split = i % 3 == 0 ? Split::kTest : Split::kTrain;
  WriteDataset(data, tmp.path("split.csv"));
  const CommandResult r = RunKincal("identify --nominal " + kNominal + " --data " + tmp.path("split.csv") +
                                    " --method least_squares --out " + tmp.path("id.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("80 measurements"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("held-out (40 rows)"), std::string::npos) << r.out;
}

// The CSV text with field `column` of the first data row replaced by `value`.
std::string ReplaceField(const std::string& csv, const std::string& column, const std::string& value) {
  std::istringstream in(csv);
  std::string out, line, header;
  bool replaced = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') {
      if (header.empty()) {
        header = line;
      } else if (!replaced) {
        std::vector<std::string> names, fields;
        std::istringstream h(header), f(line);
        for (std::string t; std::getline(h, t, ',');) names.push_back(t);
        for (std::string t; std::getline(f, t, ',');) fields.push_back(t);
        const size_t index = std::find(names.begin(), names.end(), column) - names.begin();
        fields.at(index) = value;
        line.clear();
        for (size_t k = 0; k < fields.size(); ++k) line += (k ? "," : "") + fields[k];
        replaced = true;
      }
    }
    out += line + "\n";
  }
  return out;
}

void ExpectRejected(const std::string& data, const std::string& reason) {
  TempDir tmp;
  const CommandResult r =
      RunKincal("identify --nominal " + kNominal + " --data " + data + " --method least_squares --out " +
                tmp.path("id.yaml") + " --report " + tmp.path("report.json"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.path("id.yaml")));
  EXPECT_FALSE(std::filesystem::exists(tmp.path("report.json")));
}

TEST(LeastSquaresCli, RejectsBadInputWithExitStatus2AndWritesNothing) {
  TempDir tmp;
  ExpectRejected(Simulate(tmp, "few.csv", 8, 4), "too few measurements");

  const std::string good = ReadText(Simulate(tmp, "good.csv", 40, 5));
  // A NaN in a measured position, and in a joint angle.
  WriteText(tmp.path("nan.csv"), ReplaceField(good, "y_mm", "nan"));
  ExpectRejected(tmp.path("nan.csv"), "nan.csv:");
  WriteText(tmp.path("nan_q.csv"), ReplaceField(good, "q3_deg", "NaN"));
  ExpectRejected(tmp.path("nan_q.csv"), "nan_q.csv:");

  // Five joint columns for a six-joint robot.
  Dataset five = ReadDataset(tmp.path("good.csv"));
  five.dof = 5;
  for (auto& m : five.rows) {
    m.q.conservativeResize(5);
    m.encoders.resize(5);
  }
  WriteDataset(five, tmp.path("five.csv"));
  ExpectRejected(tmp.path("five.csv"), "5 joint columns but the robot has 6 joints");
}

}  // namespace
}  // namespace kincal::testing
