// The example study that calibrates one simulated IRB 120 with four instruments (examples/studies/
// instruments.yaml) runs end to end, and each instrument's calibration is scored on the same targets,
// against the number of measurements and against the noise; the report's "Instruments side by side" has
// one table per instrument with both knobs.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "studies/results_files.h"
#include "studies/runner.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

TEST(InstrumentsStudy, EveryInstrumentCalibratesTheArmOnTheSameTargets) {
  TempDir tmp;
  const Study study = ReadStudyFile(SourcePath("examples/studies/instruments.yaml"));
  RunStudy(study, tmp.path("out"), StudyRunOptions());
  const ResultTable t = ReadResultTable(tmp.path("out") + "/results.csv");
  double before = 0.0;
  std::map<std::string, int> calibrated;  // dataset -> rows of least_squares without compensation
  std::map<std::string, std::map<double, double>> by_noise;  // *_noise dataset -> noise (um) -> summed error
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const std::string dataset = t.Text(r, t.Column("dataset"));
    const std::string estimator = t.Text(r, t.Column("estimator"));
    const double mean = t.Number(r, t.Column("position_error_mean_mm"));
    EXPECT_EQ(t.Text(r, t.Column("status")), "ok") << dataset << " " << estimator;
    if (estimator == "none" && dataset == "tracker") before = mean;
    if (estimator != "least_squares" || t.Text(r, t.Column("compensator")) != "-") continue;
    ++calibrated[dataset];
    // 10 um of noise: the instruments that see a length recover the arm to a few hundredths of a mm;
    // contacts with planes or sockets of unknown place see no length (the longest link is held at its
    // nominal value), so they only have to beat the uncalibrated arm.
    const bool length = dataset.rfind("tracker", 0) == 0 || dataset.rfind("distances", 0) == 0;
    const bool noise = t.Text(r, t.Column("knob")) == "noise_um";
    const double bound = length ? (noise ? 0.1 : 0.05) : 0.9;
    EXPECT_LT(mean, bound) << dataset << " " << t.Text(r, t.Column("knob_value"));
    if (noise) by_noise[dataset][t.Number(r, t.Column("knob_value"))] += mean;
  }
  EXPECT_GT(before, 1.0);  // the uncalibrated arm misses the targets by about a millimetre
  for (const char* d : {"tracker", "distances", "planes", "sockets"}) {
    EXPECT_EQ(calibrated[d], 6) << d;
    EXPECT_EQ(calibrated[std::string(d) + "_noise"], 4) << d;
  }
  // Where the instrument reads a length, 25 times the noise leaves a larger error.
  for (const char* d : {"tracker_noise", "distances_noise"}) EXPECT_GT(by_noise[d][50.0], 3.0 * by_noise[d][2.0]) << d;
  const std::string report = ReadText(tmp.path("out") + "/report.md");
  const size_t side = report.find("## Instruments side by side");
  ASSERT_NE(side, std::string::npos);
  for (const char* instrument : {"point", "distance", "plane", "socket"}) {
    const size_t table = report.find(std::string("### ") + instrument + ": targets", side);
    ASSERT_NE(table, std::string::npos) << instrument;
    const std::string text = report.substr(table, report.find("\n\n###", table + 1) - table);
    EXPECT_NE(text.find("| random poses |"), std::string::npos) << text;
    EXPECT_NE(text.find("| position noise"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace kincal::testing
