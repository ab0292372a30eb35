// least_squares specifics: options from YAML, robust losses against outliers, per-row weights, fixed
// parameters, and the seed's own sweep data (METHOD.md 2, 0.01 mm noise) scored on held-out random poses.
#include <cmath>
#include <cstdio>

#include "estimators/least_squares/least_squares_estimator.h"
#include "framework/random.h"
#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {
namespace {

TEST(LeastSquaresOptions, ReadFromYamlWithUnitsAndRejectUnknownKeys) {
  const YAML::Node node = YAML::Load(R"(
fixed: [ratios, a_2]
loss: cauchy
loss_scale: 50um
max_iterations: 12
orientation_length: 200mm
bound_angle_deg: 1.5
weights: [1, 0.5, 2]
)");
  const LeastSquaresOptions o = LeastSquaresOptions::FromYaml(node);
  EXPECT_EQ(o.error_model.fixed, (std::vector<std::string>{"ratios", "a_2"}));
  EXPECT_EQ(o.weighting.loss, "cauchy");
  EXPECT_DOUBLE_EQ(o.weighting.loss_scale, 50e-6);
  EXPECT_EQ(o.max_iterations, 12);
  EXPECT_DOUBLE_EQ(o.error_model.orientation_length, 0.2);
  EXPECT_DOUBLE_EQ(o.error_model.bounds.angle, 1.5 * M_PI / 180.0);
  EXPECT_EQ(o.weighting.weights, (std::vector<double>{1, 0.5, 2}));
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;

  EXPECT_THROW(LeastSquaresOptions::FromYaml(YAML::Load("{los: huber}")), std::invalid_argument);
  EXPECT_THROW(LeastSquaresOptions::FromYaml(YAML::Load("{weights: [1, x]}")), std::invalid_argument);
  LeastSquaresOptions bad;
  bad.weighting.loss = "tukey";
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("tukey"), std::string::npos);
  EXPECT_THROW(Estimators().Create("least_squares", YAML::Load("{loss: tukey}")), std::invalid_argument);
}

// 5 % of the rows carry a 3 mm blunder. Plain least squares is pulled away; Huber and Cauchy are not.
TEST(LeastSquares, RobustLossesResistOutliers) {
  const double noise = 10e-6;
  SimulatedCase c = RandomPoseCase(200, noise, 41);
  Rng rng(8);
  for (size_t i = 0; i < c.data.rows.size(); i += 20) {
    c.data.rows[i].p += 3e-3 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
  }
  std::map<std::string, double> heldout;
  for (const char* loss : {"none", "huber", "cauchy"}) {
    YAML::Node options;
    options["loss"] = loss;
    options["loss_scale"] = "0.05mm";
    EstimationReport report;
    const Robot identified = RunEstimator("least_squares", c.nominal, c.data, &report, options);
    EXPECT_EQ(report.status, EstimationStatus::kConverged) << loss << ": " << report.BriefReport();
    heldout[loss] = HeldOutErrors(c, identified, 300, 3).rms;
  }
  std::printf("held-out RMS with 5 %% blunders: none %.4f mm, huber %.4f mm, cauchy %.4f mm\n", heldout["none"] * 1e3,
              heldout["huber"] * 1e3, heldout["cauchy"] * 1e3);
  EXPECT_GT(heldout["none"], 10 * noise);
  EXPECT_LT(heldout["huber"], 0.5 * heldout["none"]);
  EXPECT_LT(heldout["cauchy"], 2 * noise);
}

// A zero weight removes a row: the result equals the fit without it.
TEST(LeastSquares, ZeroWeightsEqualDroppingRows) {
  const SimulatedCase c = RandomPoseCase(60, 20e-6, 43);
  Dataset kept = c.data;
  kept.rows.clear();
  // Both run to the rounding level of the minimum, so that they agree to far below the noise (20 um):
  // 1e-10 m and 1e-10 relative leave room for the different summation order of the two normal equations.
  YAML::Node options, tight;
  options["parameter_tolerance"] = tight["parameter_tolerance"] = 1e-12;
  for (size_t i = 0; i < c.data.rows.size(); ++i) {
    const bool keep = i % 4 != 0;
    options["weights"].push_back(keep ? 1.0 : 0.0);
    if (keep) kept.rows.push_back(c.data.rows[i]);
  }
  EstimationReport weighted, dropped;
  const Robot a = RunEstimator("least_squares", c.nominal, c.data, &weighted, options);
  const Robot b = RunEstimator("least_squares", c.nominal, kept, &dropped, tight);
  const Eigen::VectorXd da = a.model().Parameters(), db = b.model().Parameters();
  EXPECT_LT((da - db).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((a.drives->ratio - b.drives->ratio).cwiseQuotient(b.drives->ratio).cwiseAbs().maxCoeff(), 1e-10);

  YAML::Node wrong;
  wrong["weights"].push_back(1.0);
  EXPECT_THROW(RunEstimator("least_squares", c.nominal, c.data, &weighted, wrong), std::invalid_argument);
}

TEST(LeastSquares, FixedParametersKeepTheirValueAndSayWhy) {
  const SimulatedCase c = RandomPoseCase(60, 0.0, 47);
  EstimationReport report;
  const Robot identified =
      RunEstimator("least_squares", c.nominal, c.data, &report, YAML::Load("{fixed: [ratios, a_3]}"));
  for (const auto& p : report.parameters) {
    if (p.name.rfind("ratio_", 0) == 0 || p.name == "a_3") {
      EXPECT_FALSE(p.free) << p.name;
      EXPECT_EQ(p.note, "fixed by the options") << p.name;
      EXPECT_EQ(p.value, p.nominal) << p.name;
    }
  }
  EXPECT_EQ(identified.drives->ratio, c.nominal.drives->ratio);
  EXPECT_EQ(identified.model().Parameter("a_3"), c.nominal.model().Parameter("a_3"));
  // The ratios' errors cannot be absorbed: the fit is worse than the truth would be.
  EXPECT_GT(report.final_rms, 1e-5);
}

// The seed's protocol: joints swept one at a time from the calibration configuration, 20 stops 2 deg apart.
// Noise-free sweeps determine every identifiable parameter exactly ...
TEST(LeastSquares, NoiseFreeSweepDataGivesTheTruth) {
  const SimulatedCase c = SweepCase(0.0, 1);
  EstimationReport report;
  const Robot identified = RunEstimator("least_squares", c.nominal, c.data, &report, YAML::Node());
  EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
  EXPECT_LT(HeldOutErrors(c, identified, 300, 1001).max, 1e-10);
}

// ... and with 0.01 mm noise the short arcs (38 deg per joint) leave parameter standard deviations of
// 0.1 to 0.5 mm, which extrapolate to the whole workspace. The lead compares this held-out error with the
// geometric method's on the same data.
TEST(LeastSquares, SeedSweepDataHeldOutError) {
  const double noise = 10e-6;
  std::vector<double> rms;
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    const SimulatedCase c = SweepCase(noise, seed);
    EstimationReport report;
    const Robot identified = RunEstimator("least_squares", c.nominal, c.data, &report, YAML::Node());
    EXPECT_EQ(report.status, EstimationStatus::kConverged) << report.BriefReport();
    const ErrorStats heldout = HeldOutErrors(c, identified, 300, 1000 + seed);
    Robot placed = c.nominal;  // the nominal robot seen from the true tracker frame
    placed.model().SetBase(c.truth.model().base());
    const ErrorStats nominal = HeldOutErrors(c, placed, 300, 1000 + seed);
    rms.push_back(heldout.rms);
    std::string fixed;
    for (const auto& f : report.fixed_parameters) fixed += " " + f;
    std::printf(
        "sweep seed %d: %d rows, %s\n  held (not identifiable):%s; condition number %.4g\n"
        "  held-out on 300 random poses: mean %.4f mm, RMS %.4f mm, max %.4f mm (nominal robot in the true frame: RMS "
        "%.3f mm)\n",
        static_cast<int>(seed), static_cast<int>(c.data.rows.size()), report.BriefReport().c_str(), fixed.c_str(),
        report.condition_number, heldout.mean * 1e3, heldout.rms * 1e3, heldout.max * 1e3, nominal.rms * 1e3);
    EXPECT_LT(heldout.rms, 0.5 * nominal.rms);
  }
  double mean = 0.0;
  for (double r : rms) mean += r / rms.size();
  std::printf("sweep data, least_squares: mean held-out RMS over 5 noise draws %.4f mm\n", mean * 1e3);
}

}  // namespace
}  // namespace kincal::testing
