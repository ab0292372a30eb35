// Measured data as whitespace tables (framework/pose_tables.h) and studies on them: the reader's errors,
// splits that keep a pose's markers together, the "before" baseline that places the nominal robot in the
// instrument's frame, at-bounds statuses, and the held-out table and plots of error against reach and speed.
#include <fstream>

#include <gtest/gtest.h>

#include "framework/pose_tables.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "studies/results_files.h"
#include "studies/runner.h"
#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::ReadText;
using testing::TempDir;
using testing::WriteText;

std::string ErrorOf(const PoseTables& t, int dof) {
  try {
    ReadPoseTables(t, dof);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(PoseTables, OneRowPerPoseAndMarkerInMeasurementOrder) {
  TempDir tmp;
  WriteText(tmp.path("q.txt"), "# controller readings\n10 20\n\n30 40\n");
  WriteText(tmp.path("a.txt"), "1 2 3\n4 5 6\n");
  WriteText(tmp.path("b.txt"), "7,8,9\n10 11 12\n");
  PoseTables t;
  t.joints = tmp.path("q.txt");
  t.positions = {{"A", tmp.path("a.txt")}, {"B", tmp.path("b.txt")}};
  const Dataset d = ReadPoseTables(t, 2);
  ASSERT_EQ(d.rows.size(), 4u);
  EXPECT_EQ(d.rows[0].marker, "A");
  EXPECT_EQ(d.rows[1].marker, "B");
  EXPECT_EQ(d.rows[1].q, d.rows[0].q);
  EXPECT_DOUBLE_EQ(d.rows[2].q[1], 40 * M_PI / 180);
  EXPECT_DOUBLE_EQ(d.rows[3].p.z(), 0.012);
  EXPECT_EQ(d.rows[2].line, 4);
  // The previous pose of both rows of pose 2 is pose 1 (rows of one pose share it).
  const auto previous = d.PreviousPoses();
  EXPECT_EQ(previous[2].row, 1);
  EXPECT_EQ(*d.PreviousQ(previous[3]), d.rows[0].q);
}

// Tables filtered from a longer sequence (irb120_faro: 982 of 1000 poses): a pose that followed a removed
// one was reached from it, and the unfiltered readings say so.
TEST(PoseTables, TheUnfilteredSequenceGivesEachPoseTheOneItCameFrom) {
  TempDir tmp;
  // Sequence: A B C C D E F (C measured twice in a row); kept: A C D F, with C's readings printed with
  // more digits. B and E were removed.
  WriteText(tmp.path("all.txt"), "1 1\n2 2\n3 3\n3 3\n4 4\n5 5\n6 6\n");
  WriteText(tmp.path("q.txt"), "1 1\n3.0000000001 3\n4 4\n6 6\n");
  WriteText(tmp.path("p.txt"), "0 0 0\n0 0 0\n0 0 0\n0 0 0\n");
  PoseTables t;
  t.joints = tmp.path("q.txt");
  t.positions = {{"A", tmp.path("p.txt")}, {"B", tmp.path("p.txt")}};
  const Dataset plain = ReadPoseTables(t, 2);
  EXPECT_FALSE(plain.HasFromColumns());
  t.sequence = tmp.path("all.txt");
  const Dataset d = ReadPoseTables(t, 2);
  ASSERT_EQ(d.rows.size(), 8u);
  const auto deg = [](double a, double b) -> Eigen::VectorXd { return Eigen::Vector2d(a, b) * (M_PI / 180); };
  const auto previous = d.PreviousPoses();
  // Pose A: the first of the sequence, none.
  EXPECT_EQ(d.PreviousQ(previous[0]), nullptr);
  // Pose C: reached from B (removed), not from A; both of its rows (markers A and B).
  for (int r : {2, 3}) {
    ASSERT_NE(d.PreviousQ(previous[r]), nullptr);
    EXPECT_TRUE(d.PreviousQ(previous[r])->isApprox(deg(2, 2))) << r;
  }
  // Pose D: from C, the pose before it in the table too: no from_q needed.
  EXPECT_FALSE(d.rows[4].from_q.has_value());
  EXPECT_TRUE(d.PreviousQ(previous[4])->isApprox(deg(3.0000000001, 3)));
  // Pose F: from E (removed).
  EXPECT_TRUE(d.PreviousQ(previous[6])->isApprox(deg(5, 5)));
  // The previous poses survive a split (SelectRows) and a CSV round trip (from_q columns).
  const Dataset odd = d.SelectRows({2, 3, 6, 7});
  EXPECT_TRUE(odd.rows[0].from_q->isApprox(deg(2, 2)));
  const Dataset back = ParseDatasetCsv(DatasetToCsv(d), "back.csv");
  const auto back_previous = back.PreviousPoses();
  for (size_t r = 0; r < d.rows.size(); ++r) {
    const Eigen::VectorXd* a = d.PreviousQ(previous[r]);
    const Eigen::VectorXd* b = back.PreviousQ(back_previous[r]);
    ASSERT_EQ(a == nullptr, b == nullptr) << r;
    if (a) {
      EXPECT_TRUE(a->isApprox(*b, 1e-12)) << r;
    }
  }

  // A pose missing from the sequence, or out of its order: file, line, column.
  WriteText(tmp.path("q_bad.txt"), "1 1\n4 4\n3 3\n");
  WriteText(tmp.path("p3.txt"), "0 0 0\n0 0 0\n0 0 0\n");
  t.joints = tmp.path("q_bad.txt");
  t.positions = {{"A", tmp.path("p3.txt")}};
  EXPECT_EQ(ErrorOf(t, 2), tmp.path("q_bad.txt") + ":3:1: this pose is not in the sequence " + tmp.path("all.txt") +
                               " after its line 5 (the joints table must be the sequence with rows removed, in order)");
  t.sequence = tmp.path("nowhere.txt");
  EXPECT_NE(ErrorOf(t, 2).find("nowhere.txt"), std::string::npos);
}

TEST(PoseTables, BadTablesNameFileLineAndColumn) {
  TempDir tmp;
  WriteText(tmp.path("q.txt"), "10 20\n30 x40\n");
  WriteText(tmp.path("q3.txt"), "10 20\n30 40 50\n");
  WriteText(tmp.path("q_ok.txt"), "10 20\n30 40\n");
  WriteText(tmp.path("p.txt"), "1 2 3\n");
  WriteText(tmp.path("p_nan.txt"), "1 2 3\n4 nan 6\n");
  PoseTables t;
  t.joints = tmp.path("q.txt");
  t.positions = {{"A", tmp.path("p.txt")}};
  EXPECT_EQ(ErrorOf(t, 2), tmp.path("q.txt") + ":2:4: expected a finite number, got 'x40'");
  t.joints = tmp.path("q3.txt");
  EXPECT_EQ(ErrorOf(t, 2), tmp.path("q3.txt") + ":2:1: expected 2 numbers, got 3");
  t.joints = tmp.path("q_ok.txt");
  EXPECT_NE(ErrorOf(t, 2).find(tmp.path("p.txt") + ":1:1: expected 2 rows"), std::string::npos);
  t.positions = {{"A", tmp.path("p_nan.txt")}};
  EXPECT_EQ(ErrorOf(t, 2), tmp.path("p_nan.txt") + ":2:3: expected a finite number, got 'nan'");
  t.positions = {{"A", tmp.path("missing.txt")}};
  EXPECT_NE(ErrorOf(t, 2).find("missing.txt"), std::string::npos);
}

// The seed's arm as a tracker sees it: 1.5 m away, two reflectors on the tool, measured in order.
class MeasuredTablesStudy : public ::testing::Test {
 protected:
  void SetUp() override {
    Robot truth = testing::SeedTruth();
    Eigen::Isometry3d T_meas_base = Eigen::Isometry3d::Identity();
    T_meas_base.translation() = Eigen::Vector3d(1.5, -0.4, 0.2);
    T_meas_base.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    truth.model().SetBase(T_meas_base);
    const Eigen::Vector3d markers[2] = {{0.12, 0.0, 0.05}, {-0.03, 0.1, 0.06}};
    std::ofstream q(tmp_.path("q.txt"));
    std::ofstream p[2] = {std::ofstream(tmp_.path("m1.txt")), std::ofstream(tmp_.path("m2.txt"))};
    for (int k = 0; k < 2; ++k) {
      Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
      tool.translation() = markers[k];
      truth.model().SetTool(tool);
      SimulatorOptions o;
      o.protocol = "random";
      o.poses = 60;
      o.noise_sigma = 20e-6;
      o.seed = 5;
      const Dataset d = Simulate(testing::SeedNominal(), truth, o);
      for (const Measurement& m : d.rows) {
        if (k == 0) q << (m.q * 180 / M_PI).transpose().format(Eigen::IOFormat(17)) << "\n";
        p[k] << (m.p * 1e3).transpose().format(Eigen::IOFormat(17)) << "\n";
      }
    }
    Robot nominal = testing::SeedNominal();
    nominal.markers = {{"SMR1", Eigen::Vector3d::Zero()}, {"SMR2", Eigen::Vector3d::Zero()}};
    WriteRobotFile(nominal, tmp_.path("nominal.yaml"));
  }

  std::string StudyYaml(const std::string& positions) const {
    return "name: tables\nrobots: {nominal: nominal.yaml}\n"
           "datasets:\n"
           "  - name: tracker\n"
           "    tables: {joints: q.txt, positions: " +
           positions +
           ", units: {length: mm, angle: deg}}\n"
           "    split: {every: 3}\n"
           "estimators:\n"
           "  - {name: ls, method: least_squares, options: {max_iterations: 100}}\n"
           "  - {name: tight, method: nlopt, options: {bound_length: 1um, bound_angle_deg: 0.0001}}\n";
  }

  ResultTable Run(const std::string& positions, const std::string& out) {
    WriteText(tmp_.path("study.yaml"), StudyYaml(positions));
    const Study s = ReadStudyFile(tmp_.path("study.yaml"));
    RunStudy(s, tmp_.path(out), StudyRunOptions());
    return ReadResultTable(tmp_.path(out) + "/results.csv");
  }

  static std::string Cell(const ResultTable& t, const std::string& estimator, const std::string& column) {
    for (size_t r = 0; r < t.rows.size(); ++r) {
      if (t.Text(r, t.Column("estimator")) == estimator) return t.Text(r, t.Column(column));
    }
    return "";
  }

  TempDir tmp_;
};

TEST_F(MeasuredTablesStudy, BeforeIsTheNominalPlacedAndPosesStayTogether) {
  const ResultTable t = Run("{SMR1: m1.txt, SMR2: m2.txt}", "out");
  // Every 3rd pose of 60 is a test pose, both of its markers: 40 rows.
  EXPECT_EQ(Cell(t, "none", "targets"), "40");
  const double before = std::stod(Cell(t, "none", "position_error_rms_mm"));
  const double after = std::stod(Cell(t, "ls", "position_error_rms_mm"));
  // The nominal robot unplaced is 1.5 m off; placed (base and markers fitted), the seed's geometric errors
  // remain: millimetres. The full fit reaches the noise (20 um per axis).
  EXPECT_GT(before, 0.5);
  EXPECT_LT(before, 20.0);
  EXPECT_LT(after, 0.08);
  EXPECT_EQ(Cell(t, "ls", "status"), "ok");
  // Bounds of 1 um and 1e-4 deg cannot hold the seed's errors: the status says so.
  EXPECT_EQ(Cell(t, "tight", "status"), "estimate_at_bounds");
  EXPECT_NE(Cell(t, "tight", "note").find("on their bounds"), std::string::npos);

  const ResultTable h = ReadResultTable(tmp_.path("out") + "/heldout.csv");
  ASSERT_EQ(h.rows.size(), 3u * 40u);
  for (size_t r = 0; r < h.rows.size(); ++r) {
    EXPECT_GT(h.Number(r, h.Column("reach_mm")), 0.0);
    EXPECT_TRUE(std::isnan(h.Number(r, h.Column("approach_speed_deg_s"))));  // no velocity limits
  }
  const std::string report = ReadText(tmp_.path("out") + "/report.md");
  EXPECT_NE(report.find("Held-out error against reach"), std::string::npos);
  EXPECT_NE(report.find("nominal geometry with only the base"), std::string::npos);
}

TEST_F(MeasuredTablesStudy, TablesWithoutASplitAreRefusedWithTheirKey) {
  WriteText(tmp_.path("bad.yaml"),
            "name: t\nrobots: {nominal: nominal.yaml}\ndatasets:\n  - name: a\n    tables: {joints: q.txt, positions: "
            "{SMR1: m1.txt}}\nestimators: [least_squares]\n");
  try {
    ReadStudyFile(tmp_.path("bad.yaml"));
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:5:13: datasets[0].tables: tables have no split column"),
              std::string::npos)
        << e.what();
  }
  WriteText(tmp_.path("bad2.yaml"),
            "name: t\nrobots: {nominal: nominal.yaml}\ndatasets:\n  - name: a\n    tables: {joints: q.txt, positions: "
            "{SMR1: nowhere.txt}}\n    split: {every: 2}\nestimators: [least_squares]\n");
  try {
    ReadStudyFile(tmp_.path("bad2.yaml"));
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("datasets[0].tables.positions.SMR1: cannot read"), std::string::npos)
        << e.what();
  }
  WriteText(tmp_.path("bad3.yaml"),
            "name: t\nrobots: {nominal: nominal.yaml}\ndatasets:\n  - name: a\n    tables: {joints: q.txt, positions: "
            "{SMR1: m1.txt}, sequence: nowhere.txt}\n    split: {every: 2}\nestimators: [least_squares]\n");
  try {
    ReadStudyFile(tmp_.path("bad3.yaml"));
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("datasets[0].tables.sequence: cannot read"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace kincal
