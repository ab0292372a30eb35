// The real UR10 of ../shared/data/ur10_ipa2021 (the README's "Real data" figures; skips without the data,
// fails with KINCAL_REQUIRE_DATA=1):
// - positions only, least_squares, max_iterations 200, examples/robots/ur10_joint_errors.yaml truncated to
//   each row's terms (geometry; + gravity 2, 3; + gravity 4, 5; + harmonic 1, 2 on every joint; + approach
//   and backlash on every joint): held-out RMS and max per series (even rows fit, odd scored) and B -> C
//   (C's first 20 poses re-register its base);
// - full pose on series D: position and orientation residuals weighed by orientation_length (reported),
//   and the source's Euler angles read as intrinsic XYZ (the extrinsic reading leaves degrees);
// - ISO 9283 of series D's repeated poses through examples/studies/ur10_ipa2021.yaml, and the same AP
//   from the data's own commanded poses (Goal columns) registered rigidly onto the measured ones.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimators/error_model/prediction_uncertainty.h"
#include "estimators/estimator.h"
#include "estimators/selection/model_selection.h"
#include "framework/dataset.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "studies/measured_iso9283.h"
#include "tests/real_data/ur10_ipa2021_util.h"

namespace kincal::testing {
namespace {

// One folder for the converted datasets of this program.
TempDir& Folder() {
  static TempDir dir;
  return dir;
}

// `name`.csv converted once with `arguments` (the series are given as kUr10A..D keys: "A", "B", ...).
std::string Converted(const std::string& name, const std::string& arguments) {
  static std::map<std::string, std::string> done;
  if (done.count(name)) return done[name];
  const std::string path = Folder().path(name + ".csv");
  std::string err;
  if (RunUr10Converter(arguments + " --out '" + path + "'", Folder(), &err) != 0) {
    ADD_FAILURE() << "converter failed: " << err;
    return "";
  }
  return done[name] = path;
}

std::string Series(const char* file) { return "'" + Ur10Series(file) + "'"; }

std::string TableDataset(const std::string& series) {
  if (series == "BC") return Converted("bc", Series(kUr10B) + " " + Series(kUr10C) + " --reregister 20");
  const std::map<std::string, const char*> files = {{"A", kUr10A}, {"B", kUr10B}, {"C", kUr10C}, {"D", kUr10D}};
  return Converted(series, Series(files.at(series)) + " --split even-odd");
}

// examples/robots/ur10_joint_errors.yaml with its first `terms` joint-error entries (0: geometry only).
Robot Ur10WithTerms(int terms) {
  std::istringstream in(ReadText(SourcePath("examples/robots/ur10_joint_errors.yaml")));
  std::ostringstream out;
  int seen = -1;  // -1: before `joint_errors:`
  for (std::string line; std::getline(in, line);) {
    if (line == "joint_errors:") {
      seen = 0;
      if (terms > 0) out << line << "\n";
      continue;
    }
    if (seen >= 0 && line.rfind("  - ", 0) == 0 && seen++ >= terms) continue;
    out << line << "\n";
  }
  return ParseRobotYaml(out.str(), "ur10_joint_errors.yaml (first " + std::to_string(terms) + " terms)");
}

// `nominal` fitted by least_squares with `options` (YAML) on the training rows of `all`.
EstimationReport FitTrainingRows(const Robot& nominal, const Dataset& all, const std::string& options,
                                 Robot* identified) {
  return Estimators().Create("least_squares", YAML::Load(options))->Estimate(nominal, all.Subset(Split::kTrain),
                                                                             identified);
}

// The tight tolerances of a held-out figure (mm): 0.5 % of an RMS, at least 0.002 mm; 1 % of a max, at
// least 0.01 mm.
double RmsTolerance(double rms_mm) { return std::max(0.002, 0.005 * rms_mm); }
double MaxTolerance(double max_mm) { return std::max(0.01, 0.01 * max_mm); }

struct TableCase {
  std::string series;  // A, B, C, D (even/odd) or BC (B -> C)
  int terms;           // joint-error entries of the robot file kept
  std::string model;
  double rms_mm, max_mm;  // held out
  // Tolerances (mm); 0: tight (0.5 % of the RMS, at least 0.002 mm; 1 % of the max, at least 0.01 mm).
  double rms_tolerance = 0.0, max_tolerance = 0.0;
};

class Ur10Table : public ::testing::TestWithParam<TableCase> {};

TEST_P(Ur10Table, HeldOutErrorOfEachModel) {
  KINCAL_UR10_DATA_OR_SKIP();
  const TableCase& c = GetParam();
  const Dataset all = ReadDataset(TableDataset(c.series));
  const Robot nominal = Ur10WithTerms(c.terms);
  Robot identified;
  const EstimationReport report = FitTrainingRows(nominal, all, "max_iterations: 200", &identified);
  const ErrorStats e = EvaluatePredictions(nominal, identified, all.Subset(Split::kTest)).position_stats;
  std::printf("series %s, %s: held-out RMS %.4f mm, max %.4f mm (%s, %d iterations)\n", c.series.c_str(),
              c.model.c_str(), e.rms * 1e3, e.max * 1e3, ToString(report.status).c_str(), report.iterations);
  EXPECT_NE(report.status, EstimationStatus::kFailed) << report.BriefReport();
  EXPECT_NEAR(e.rms * 1e3, c.rms_mm, c.rms_tolerance > 0 ? c.rms_tolerance : RmsTolerance(c.rms_mm));
  EXPECT_NEAR(e.max * 1e3, c.max_mm, c.max_tolerance > 0 ? c.max_tolerance : MaxTolerance(c.max_mm));
}

const char* kGeometry = "geometry";
const char* kGravity23 = "+ gravity 2, 3";
const char* kGravity25 = "+ gravity 2-5";
const char* kHarmonic = "+ harmonic 1, 2";
const char* kApproach = "+ approach, backlash";

// The rows of the table (each measured with this build; a fit that ends in a flat valley is analysed
// there: its weak parameters named, those without a prior held, and fitted again with a budget of its own).
const std::vector<TableCase>& TableCases() {
  static const std::vector<TableCase> cases = {
      TableCase{"D", 0, kGeometry, 0.4073, 1.3310},    TableCase{"D", 2, kGravity23, 3.1096, 54.9231},
      TableCase{"D", 4, kGravity25, 1.3481, 23.1314}, TableCase{"D", 10, kHarmonic, 1.6409, 28.4024},
      TableCase{"D", 22, kApproach, 1.5784, 27.2550},  TableCase{"BC", 0, kGeometry, 0.6289, 1.8892},
      TableCase{"BC", 2, kGravity23, 0.5452, 1.6220},  TableCase{"BC", 4, kGravity25, 0.6222, 1.7034},
      TableCase{"BC", 10, kHarmonic, 0.6839, 2.0468},  TableCase{"BC", 22, kApproach, 0.6818, 2.0182},
      TableCase{"A", 0, kGeometry, 0.4406, 1.1444},    TableCase{"A", 2, kGravity23, 0.4196, 1.2247},
      TableCase{"A", 4, kGravity25, 0.4193, 1.2127},   TableCase{"A", 10, kHarmonic, 0.4107, 1.1848},
      TableCase{"A", 22, kApproach, 0.4055, 1.1503},   TableCase{"B", 0, kGeometry, 0.4587, 2.0280},
      TableCase{"B", 2, kGravity23, 0.4272, 1.9785},   TableCase{"B", 4, kGravity25, 0.4124, 1.9838},
      TableCase{"B", 10, kHarmonic, 0.4236, 1.9714},   TableCase{"B", 22, kApproach, 0.4252, 1.7952},
      TableCase{"C", 0, kGeometry, 0.4948, 1.5356},    TableCase{"C", 2, kGravity23, 0.4870, 1.5325},
      TableCase{"C", 4, kGravity25, 0.4894, 1.5446},   TableCase{"C", 10, kHarmonic, 0.4835, 1.4391},
      TableCase{"C", 22, kApproach, 0.4826, 1.4592},
  };
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Rows, Ur10Table, ::testing::ValuesIn(TableCases()),
                         [](const ::testing::TestParamInfo<TableCase>& info) {
                           return info.param.series + "_terms" + std::to_string(info.param.terms);
                         });

// `select: true` from the richest file (estimators/selection; maximum a posteriori with the default priors,
// as selection fits unless the options give `prior`): the chosen candidate and its held-out error, and
// the acceptance criteria against this series' rows of the table: RMS <= 1.05 x the best row and never
// above geometry's, max <= 1.5 x geometry's.
struct SelectCase {
  std::string series;
  std::string chosen;
  double rms_mm, max_mm;
  double coverage;  // held-out 3-D errors within 3 sqrt(sd_pred^2 + sigma_3d^2) (prediction_uncertainty.h (2))
};

class Ur10Select : public ::testing::TestWithParam<SelectCase> {};

TEST_P(Ur10Select, HeldOutErrorOfTheSelectedModel) {
  KINCAL_UR10_DATA_OR_SKIP();
  const SelectCase& c = GetParam();
  const Dataset all = ReadDataset(TableDataset(c.series));
  const Robot nominal = Ur10WithTerms(22);
  Robot identified;
  const EstimationReport report = FitTrainingRows(nominal, all, "{max_iterations: 200, select: true}", &identified);
  const std::string chosen = ChosenCandidate(report.details.at("selection"));
  const Dataset test = all.Subset(Split::kTest);
  const PredictionErrors errors = EvaluatePredictions(nominal, identified, test);
  const ErrorStats& e = errors.position_stats;
  const PredictionCovariance cov = PredictionCovariance::FromJson(report.details.at("prediction_covariance"));
  const std::vector<double> sd = PredictionSd(identified, nominal, test, cov);
  const UncertaintyCheck check = CheckUncertainty(errors.position, sd, cov, test);
  const double coverage = check.coverage;
  PredictionCovariance parameters = cov;  // the bound of (1) alone, without the model-inadequacy tau
  parameters.inadequacy = 0.0;
  parameters.inadequacy_beyond.clear();
  std::string beyond;
  for (double t : cov.inadequacy_beyond) beyond += " " + std::to_string(t * 1e3).substr(0, 6);
  std::printf("series %s, selected %s: held-out RMS %.4f mm, max %.4f mm, coverage %.4f (supported %.4f; "
              "parameters' part alone %.4f); tau %.4f mm, beyond joint 1..6:%s mm\n",
              c.series.c_str(), chosen.c_str(), e.rms * 1e3, e.max * 1e3, coverage, check.coverage_supported,
              CheckUncertainty(errors.position, sd, parameters, test).coverage, cov.inadequacy * 1e3, beyond.c_str());
  EXPECT_EQ(chosen, c.chosen);
  EXPECT_NEAR(coverage, c.coverage, 0.002);
  EXPECT_GE(coverage, 0.95);
  EXPECT_NEAR(e.rms * 1e3, c.rms_mm, RmsTolerance(c.rms_mm));
  EXPECT_NEAR(e.max * 1e3, c.max_mm, MaxTolerance(c.max_mm));
  double best = 1e9, geometry_rms = 0.0, geometry_max = 0.0;
  for (const TableCase& row : TableCases()) {
    if (row.series != c.series) continue;
    best = std::min(best, row.rms_mm);
    if (row.terms == 0) geometry_rms = row.rms_mm, geometry_max = row.max_mm;
  }
  std::printf("  against the table: best row %.4f mm, geometry %.4f / %.4f mm\n", best, geometry_rms, geometry_max);
  EXPECT_LE(e.rms * 1e3, 1.05 * best);
  EXPECT_LE(e.rms * 1e3, geometry_rms);
  EXPECT_LE(e.max * 1e3, 1.5 * geometry_max);
}

// With `prior: off` (least-squares candidates, measured before fits were analysed in flat valleys) the
// choices were the same but for D (geometry), and B held out 0.466 mm, above geometry's 0.459.
INSTANTIATE_TEST_SUITE_P(Series, Ur10Select,
                         ::testing::Values(SelectCase{"A", "+ compliance 2", 0.4235, 1.2114, 1.0000},
                                           SelectCase{"B", "+ gravity 2", 0.4163, 1.9776, 0.9987},
                                           SelectCase{"C", "+ harmonic 5", 0.4814, 1.4797, 0.9993},
                                           SelectCase{"D", "+ compliance 2", 0.3530, 0.8698, 1.0000},
                                           SelectCase{"BC", "+ harmonic 2", 0.5536, 1.5750, 0.9978}),
                         [](const ::testing::TestParamInfo<SelectCase>& info) { return info.param.series; });

// `prior: on` (maximum a posteriori, error_model_problem.h's default prior sds) on the richest file, no
// selection: the held-out error, beside geometry's (the first row of the table).
struct PriorCase {
  std::string series;
  double rms_mm, max_mm;
};

class Ur10Prior : public ::testing::TestWithParam<PriorCase> {};

TEST_P(Ur10Prior, HeldOutErrorOfTheRichestFileWithPriors) {
  KINCAL_UR10_DATA_OR_SKIP();
  const PriorCase& c = GetParam();
  const Dataset all = ReadDataset(TableDataset(c.series));
  const Robot nominal = Ur10WithTerms(22);
  Robot identified;
  const EstimationReport report = FitTrainingRows(nominal, all, "{max_iterations: 200, prior: on}", &identified);
  const ErrorStats e = EvaluatePredictions(nominal, identified, all.Subset(Split::kTest)).position_stats;
  std::printf("series %s, prior: on: held-out RMS %.4f mm, max %.4f mm (%s)\n", c.series.c_str(), e.rms * 1e3,
              e.max * 1e3, ToString(report.status).c_str());
  EXPECT_NE(report.status, EstimationStatus::kFailed) << report.BriefReport();
  EXPECT_NEAR(e.rms * 1e3, c.rms_mm, RmsTolerance(c.rms_mm));
  EXPECT_NEAR(e.max * 1e3, c.max_mm, MaxTolerance(c.max_mm));
}

INSTANTIATE_TEST_SUITE_P(Series, Ur10Prior,
                         ::testing::Values(PriorCase{"A", 0.4056, 1.1593}, PriorCase{"B", 0.4155, 1.7928},
                                           PriorCase{"C", 0.4804, 1.5076}, PriorCase{"D", 0.3574, 1.0106},
                                           PriorCase{"BC", 0.5659, 1.8242}),
                         [](const ::testing::TestParamInfo<PriorCase>& info) { return info.param.series; });

// Full pose, series D, even rows fit: position and orientation both held out; the weight is reported.
struct FullPose {
  ErrorStats position, orientation;
  EstimationReport report;
};
FullPose FitFullPose(const std::string& data_path, const std::string& options) {
  const Dataset all = ReadDataset(data_path);
  const Robot nominal = Ur10WithTerms(0);
  Robot identified;
  FullPose f;
  f.report = FitTrainingRows(nominal, all, options, &identified);
  const PredictionErrors e = EvaluatePredictions(nominal, identified, all.Subset(Split::kTest));
  f.position = e.position_stats;
  f.orientation = e.orientation_stats;
  return f;
}

TEST(Ur10FullPose, SeriesDPositionAndOrientationHeldOut) {
  KINCAL_UR10_DATA_OR_SKIP();
  const std::string d = Converted("d_full", Series(kUr10D) + " --pose full --split even-odd");
  const FullPose f = FitFullPose(d, "max_iterations: 200");
  std::printf(
      "series D, full pose (orientation_length 0.1 m/rad): held out %.4f mm RMS (max %.4f), %.4f mrad RMS (max %.4f)\n",
      f.position.rms * 1e3, f.position.max * 1e3, f.orientation.rms * 1e3, f.orientation.max * 1e3);
  EXPECT_EQ(f.report.status, EstimationStatus::kConverged) << f.report.BriefReport();
  EXPECT_EQ(f.orientation.count, 316);
  EXPECT_NEAR(f.position.rms * 1e3, 0.4072, 0.002);
  EXPECT_NEAR(f.orientation.rms * 1e3, 1.0955, 0.005);
  ASSERT_TRUE(f.report.details.contains("orientation_length_m_per_rad"));
  EXPECT_EQ(f.report.details["orientation_length_m_per_rad"].get<double>(), 0.1);
  // A heavier orientation weight trades a little position for orientation, and is reported as given.
  const FullPose heavy = FitFullPose(d, "max_iterations: 200\norientation_length: 1");
  EXPECT_EQ(heavy.report.details["orientation_length_m_per_rad"].get<double>(), 1.0);
  EXPECT_LT(heavy.orientation.rms, f.orientation.rms);
  EXPECT_GT(heavy.position.rms, f.position.rms);
}

TEST(Ur10FullPose, EulerAnglesAreIntrinsicXyz) {
  KINCAL_UR10_DATA_OR_SKIP();
  const FullPose extrinsic =
      FitFullPose(Converted("d_extrinsic", Series(kUr10D) + " --pose full --split even-odd --euler extrinsic-xyz"),
                  "max_iterations: 200");
  // No geometry makes the other reading consistent: the orientation error stays at tenths of a radian.
  std::printf("series D, extrinsic reading: held out %.1f mm RMS, %.0f mrad RMS\n", extrinsic.position.rms * 1e3,
              extrinsic.orientation.rms * 1e3);
  EXPECT_GT(extrinsic.orientation.rms, 0.1);
}

}  // namespace
}  // namespace kincal::testing
