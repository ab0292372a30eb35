// The calibration doctor (doctor/doctor.h) on simulated data: an arm whose true geometry differs from
// the robot file's by a millimetre and a few hundredths of a degree per parameter, measured by a tracker
// metres away with 20 um noise. Clean data give no finding; each fault injected gives its cause, with
// the right joints or lines, and no other finding.
#include <algorithm>
#include <fstream>

#include <gtest/gtest.h>

#include "doctor/doctor.h"
#include "framework/random.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"

namespace kincal::testing {
namespace {

struct Case {
  Robot nominal;  // the robot file: the tool 150 mm from the flange, where the reflector is
  Dataset data;   // random poses of the truth, in the tracker's frame
};

Robot Ur10WithTool() {
  Robot r = LoadExampleRobot("ur10_dh.yaml");
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Eigen::Vector3d(0.03, 0.06, 0.15);
  r.model().SetTool(tool);
  return r;
}

// `limits`: the robot file's joint limits, rad (empty: ur10_dh.yaml's +-360 deg); the poses keep within them.
Case Simulated(int poses, uint64_t seed, std::vector<int> sweep_order = {},
               std::vector<std::pair<double, double>> limits = {}) {
  Case s{Ur10WithTool(), {}};
  if (!limits.empty()) s.nominal.limits = limits;
  Robot truth = s.nominal;
  Eigen::VectorXd p = truth.model().Parameters();
  Rng rng(seed);
  for (int i = 0; i < p.size(); ++i) p[i] += 5e-4 * rng.Normal();  // 0.5 mm, 0.03 deg
  truth.model().SetParameters(p);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d(0.1, 0.2, 1.0).normalized()).toRotationMatrix();
  base.translation() = Eigen::Vector3d(2.0, -0.5, -0.4);
  truth.model().SetBase(base);
  SimulatorOptions so;
  so.protocol = sweep_order.empty() ? "random" : "sweep";
  so.poses = poses;
  so.sweep_order = sweep_order;
  so.step = 5.0 * M_PI / 180.0;
  so.seed = seed;
  s.data = WithPositionNoise(Simulate(s.nominal, truth, so), 20e-6, seed + 1);
  return s;
}

std::string Causes(const std::vector<doctor::Finding>& findings) {
  std::string out;
  for (const auto& f : findings) out += doctor::FindingLine(f) + "\n";
  return out;
}

// The one finding of `findings`, which must have cause `cause`.
doctor::Finding Only(const std::vector<doctor::Finding>& findings, const std::string& cause) {
  EXPECT_EQ(findings.size(), 1u) << Causes(findings);
  EXPECT_TRUE(!findings.empty() && findings[0].cause == cause) << Causes(findings);
  return findings.empty() ? doctor::Finding{} : findings[0];
}

TEST(Doctor, CleanDataGiveNoFinding) {
  for (uint64_t seed : {1, 2, 3}) {
    const Case s = Simulated(150, seed);
    EXPECT_TRUE(doctor::Diagnose(s.nominal, s.data).empty()) << Causes(doctor::Diagnose(s.nominal, s.data));
  }
}

// Distances to a pivot carry no point to read a cause from: the checks leave them to the fit, and still
// find a cause in the point rows of the same file.
TEST(Doctor, RowsOfOtherInstrumentsAreLeftToTheFit) {
  Case s = Simulated(150, 15);
  const Eigen::Vector3d pivot(0.7, 0.0, 0.3);
  Dataset distances = s.data;
  for (auto& m : distances.rows) {
    m.distance = (m.p - pivot).norm();
    m.p.setZero();
    m.kind = MeasurementKind::kDistance;
    m.fixture = "P1";
  }
  EXPECT_TRUE(doctor::Diagnose(s.nominal, distances).empty()) << Causes(doctor::Diagnose(s.nominal, distances));
  Dataset mixed = s.data;
  for (auto& m : mixed.rows) m.q *= M_PI / 180.0;
  for (size_t i = 0; i < 40; ++i) mixed.rows[i] = distances.rows[i];
  Only(doctor::Diagnose(s.nominal, mixed), "angle_unit");
}

TEST(Doctor, MetresUnderMillimetreHeadersAreALengthUnit) {
  Case s = Simulated(150, 4);
  for (auto& m : s.data.rows) m.p *= 1e-3;  // the file's numbers were metres, read as millimetres
  const doctor::Finding f = Only(doctor::Diagnose(s.nominal, s.data), "length_unit");
  EXPECT_LT(f.rms_repaired, 0.5 * f.rms_as_given);
}

TEST(Doctor, RadiansUnderDegreeHeadersAreAnAngleUnit) {
  Case s = Simulated(150, 5);
  for (auto& m : s.data.rows) m.q *= M_PI / 180.0;
  Only(doctor::Diagnose(s.nominal, s.data), "angle_unit");
}

TEST(Doctor, SwappedColumnsAreAJointOrderNamingBoth) {
  Case s = Simulated(150, 6);
  for (auto& m : s.data.rows) std::swap(m.q[1], m.q[4]);
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "joint_order").joints, (std::vector<int>{2, 5}));
}

TEST(Doctor, ANegatedColumnIsAJointDirection) {
  Case s = Simulated(150, 7);
  for (auto& m : s.data.rows) m.q[3] = -m.q[3];
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "joint_direction").joints, (std::vector<int>{4}));
}

TEST(Doctor, AZeroNinetyDegreesOffIsAJointOffset) {
  Case s = Simulated(150, 8);
  for (auto& m : s.data.rows) m.q[2] += M_PI / 2;
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "joint_offset").joints, (std::vector<int>{3}));
}

// The UR10's first two axes meet at right angles: negating joint 1 and turning joint 2 half a turn give
// the same points up to a rigid motion (a half turn about the axis normal to both through the shoulder),
// which the measurement frame takes up. Both repairs fit to rounding, and the finding names the other.
TEST(Doctor, AMirrorPoseIsNamedWithItsTwin) {
  Case s = Simulated(150, 16);
  for (auto& m : s.data.rows) m.q[0] = -m.q[0];
  const std::vector<doctor::Finding> found = doctor::Diagnose(s.nominal, s.data);
  ASSERT_EQ(found.size(), 1u) << Causes(found);
  const doctor::Finding& f = found[0];
  ASSERT_EQ(f.alternatives.size(), 1u) << f.message;
  const bool direction = f.cause == "joint_direction";
  EXPECT_EQ(f.joints, (std::vector<int>{direction ? 1 : 2}));
  EXPECT_EQ(f.alternatives[0].cause, direction ? "joint_offset" : "joint_direction");
  EXPECT_EQ(f.alternatives[0].joints, (std::vector<int>{direction ? 2 : 1}));
  EXPECT_NEAR(f.alternatives[0].rms_repaired, f.rms_repaired, 1e-6 * f.rms_repaired);
  EXPECT_NE(f.message.find("cannot tell"), std::string::npos) << f.message;
}

// With joint 2 limited to +-100 deg, the half turn puts most rows where the arm cannot go: the limits
// tell the twins apart, whichever of the two faults the file has.
TEST(Doctor, JointLimitsTellAMirrorPoseFromItsTwin) {
  std::vector<std::pair<double, double>> limits(6, {-2 * M_PI, 2 * M_PI});
  limits[1] = {-100 * M_PI / 180, 100 * M_PI / 180};
  const Case s = Simulated(150, 17, {}, limits);
  Dataset reversed = s.data, turned = s.data;
  for (auto& m : reversed.rows) m.q[0] = -m.q[0];
  for (auto& m : turned.rows) m.q[1] += M_PI;
  const doctor::Finding a = Only(doctor::Diagnose(s.nominal, reversed), "joint_direction");
  EXPECT_EQ(a.joints, (std::vector<int>{1}));
  EXPECT_TRUE(a.alternatives.empty()) << a.message;
  EXPECT_NE(a.message.find("outside the joint limits"), std::string::npos) << a.message;
  const doctor::Finding b = Only(doctor::Diagnose(s.nominal, turned), "joint_offset");
  EXPECT_EQ(b.joints, (std::vector<int>{2}));
  EXPECT_TRUE(b.alternatives.empty()) << b.message;
}

TEST(Doctor, AToolFarFromTheFilesIsTheTool) {
  const Case s = Simulated(150, 9);
  Robot file = s.nominal;
  Eigen::Isometry3d tool = file.model().tool();
  tool.translation() += Eigen::Vector3d(0.08, -0.04, 0.05);
  file.model().SetTool(tool);
  Only(doctor::Diagnose(file, s.data), "tool");
}

TEST(Doctor, GrossDropoutsAreOutliersByLine) {
  Case s = Simulated(150, 10);
  for (int i : {10, 57, 120}) s.data.rows[i].p += Eigen::Vector3d(0.02, -0.01, 0.015);
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "outliers").lines, (std::vector<int>{11, 58, 121}));
}

TEST(Doctor, AFrameJumpIsTheInstrumentMovedFromItsLine) {
  Case s = Simulated(150, 11);
  Eigen::Isometry3d bump = Eigen::Isometry3d::Identity();
  bump.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  bump.translation() = Eigen::Vector3d(0.01, 0.0, -0.005);
  for (size_t i = 90; i < s.data.rows.size(); ++i) s.data.rows[i].p = bump * s.data.rows[i].p;
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "instrument_moved").lines, (std::vector<int>{91}));
  // A turn about the centre of the points measured after it shifts their mean residual by nothing: the
  // change point is a rigid motion's, not a mean shift's.
  Case turn = Simulated(150, 11);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (size_t i = 60; i < turn.data.rows.size(); ++i) centre += turn.data.rows[i].p / 90.0;
  const Eigen::Isometry3d about = Eigen::Translation3d(centre) *
                                  Eigen::AngleAxisd(0.005, Eigen::Vector3d(1, 2, 2).normalized()) *
                                  Eigen::Translation3d(-centre);
  for (size_t i = 60; i < turn.data.rows.size(); ++i) turn.data.rows[i].p = about * turn.data.rows[i].p;
  EXPECT_EQ(Only(doctor::Diagnose(turn.nominal, turn.data), "instrument_moved").lines, (std::vector<int>{61}));
}

TEST(Doctor, AJointNeverSweptIsNotMoved) {
  const Case s = Simulated(1, 12, {6, 4, 3, 2, 1});  // sweeps of every joint but 5
  EXPECT_EQ(Only(doctor::Diagnose(s.nominal, s.data), "joint_not_moved").joints, (std::vector<int>{5}));
}

TEST(Doctor, SessionsAreFramesOfTheirOwnNotAJump) {
  Case s = Simulated(150, 13);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(0.5, 0.3, 0.0);
  for (size_t i = 0; i < s.data.rows.size(); ++i) {
    s.data.rows[i].session = i < 70 ? 1 : 2;  // the instrument moved on purpose
    if (i >= 70) s.data.rows[i].p = moved * s.data.rows[i].p;
  }
  EXPECT_TRUE(doctor::Diagnose(s.nominal, s.data).empty()) << Causes(doctor::Diagnose(s.nominal, s.data));
}

TEST(Doctor, CheckCommandReportsByLineAndExitsTwoOnUnreadableData) {
  Case s = Simulated(150, 14);
  for (int i : {20, 80}) s.data.rows[i].p += Eigen::Vector3d(0.0, 0.03, 0.0);
  TempDir dir;
  WriteDataset(s.data, dir.path("d.csv"));
  WriteText(dir.path("n.yaml"), RobotToYaml(s.nominal));
  const CommandResult ok = RunKincal("check --nominal '" + dir.path("n.yaml") + "' --data '" + dir.path("d.csv") +
                                     "' --report '" + dir.path("r.json") + "'");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir.path("r.json")));
  ASSERT_EQ(report["findings"].size(), 1u) << ok.out;
  EXPECT_EQ(report["findings"][0]["cause"], "outliers");
  // The file's lines: the header is line 1 (after any comment lines), so row i is on line header + 1 + i.
  const Dataset read = ReadDataset(dir.path("d.csv"));
  EXPECT_EQ(report["findings"][0]["lines"], nlohmann::json({read.rows[20].line, read.rows[80].line}));
  WriteText(dir.path("bad.csv"), "q1_deg,q2_deg\n1,2\n");
  const CommandResult bad = RunKincal("check --nominal '" + dir.path("n.yaml") + "' --data '" + dir.path("bad.csv") +
                                      "' --report '" + dir.path("bad.json") + "'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(std::ifstream(dir.path("bad.json")).good());
}

TEST(Doctor, ReportHasTheNamedFields) {
  const std::vector<doctor::Finding> f = {{"outliers", {}, {12, 40}, "two rows", 2e-3, 1e-3, {}}};
  const nlohmann::json j = doctor::FindingsToJson(f, 3e-3);
  EXPECT_DOUBLE_EQ(j["rms_as_given_mm"].get<double>(), 3.0);
  EXPECT_EQ(j["findings"][0]["cause"], "outliers");
  EXPECT_EQ(j["findings"][0]["lines"], nlohmann::json({12, 40}));
  EXPECT_DOUBLE_EQ(j["findings"][0]["rms_as_given_mm"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["findings"][0]["rms_repaired_mm"].get<double>(), 1.0);
  doctor::Finding twin{"joint_direction", {1}, {}, "joint 1 reversed", 0.2, 1e-3, {{"joint_offset", {2}, 1.5e-3}}};
  const nlohmann::json t = doctor::FindingsToJson({twin}, 0.2)["findings"][0]["alternatives"][0];
  EXPECT_EQ(t["cause"], "joint_offset");
  EXPECT_EQ(t["joints"], nlohmann::json({2}));
  EXPECT_DOUBLE_EQ(t["rms_repaired_mm"].get<double>(), 1.5);
}

}  // namespace
}  // namespace kincal::testing
