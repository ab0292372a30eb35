#include "doctor/doctor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

#include "doctor/checks.h"
#include "framework/math.h"

namespace kincal::doctor {
namespace {

constexpr double kDeg = 180.0 / M_PI;

std::string Format(const char* format, double a, double b = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

// A repair of the rows as read: applied to each row (its file line tells where a row sits).
struct Repair {
  Finding finding;
  std::function<void(Measurement*)> apply;
};

Dataset Apply(const Dataset& data, const Repair& repair) {
  Dataset out = data;
  for (Measurement& m : out.rows) repair.apply(&m);
  return out;
}

// The unit and column repairs: one per hypothesis, each undoing its fault.
std::vector<Repair> ColumnRepairs(const Dataset& data, const std::set<int>& still) {
  std::vector<Repair> out;
  const std::string lu = data.length_unit.name, au = data.angle_unit.name;
  for (double f : {1e3, 1e-3}) {
    const std::string looks = f > 1 ? (lu == "mm" ? "m" : "1000 x " + lu) : (lu == "m" ? "mm" : lu + " / 1000");
    out.push_back({{"length_unit", {}, {}, "the positions fit as " + looks + ", not the file's " + lu +
                                               ": convert them or name the columns' unit"},
                   [f](Measurement* m) { m->p *= f; }});
  }
  for (double f : {kDeg, 1.0 / kDeg}) {
    const std::string looks = f > 1 ? "radians" : "degrees";
    out.push_back({{"angle_unit", {}, {}, "the joint values fit as " + looks + ", not the file's " + au +
                                              ": convert them or name the columns' unit"},
                   [f](Measurement* m) { m->q *= f; }});
  }
  const int n = data.dof;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (still.count(a) || still.count(b)) continue;
      out.push_back({{"joint_order", {a + 1, b + 1}, {}, "joint columns " + std::to_string(a + 1) + " and " +
                                                              std::to_string(b + 1) + " fit swapped: swap them"},
                     [a, b](Measurement* m) { std::swap(m->q[a], m->q[b]); }});
    }
  }
  for (int j = 0; j < n; ++j) {
    if (still.count(j)) continue;
    out.push_back({{"joint_direction", {j + 1}, {}, "joint " + std::to_string(j + 1) +
                                                        " fits counting the other way: negate its values"},
                   [j](Measurement* m) { m->q[j] = -m->q[j]; }});
  }
  // The first joint's zero is the measurement frame's rotation, the last's the markers': neither shows.
  for (int j = 1; j + 1 < n; ++j) {
    if (still.count(j)) continue;
    for (int k : {1, 2, -1}) {
      const double add = k * M_PI / 2;
      out.push_back({{"joint_offset", {j + 1}, {}, "joint " + std::to_string(j + 1) + "'s zero fits " +
                                                       Format("%+.0f deg", -add * kDeg) +
                                                       " from the robot file's: add " + Format("%+.0f deg", add * kDeg) +
                                                       " to its values (or change the file's zero)"},
                     [j, add](Measurement* m) { m->q[j] += add; }});
    }
  }
  return out;
}

// The rows (indices into `r`, the likeliest first, at most `count`, `min_segment` apart) from which the
// residuals take a rigid motion of their own: on each side a small rotation and translation of the
// measurement frame, r_i ~ w x (p_i - c) + t, fitted by least squares (a bumped instrument turns as well
// as shifts, and a turn leaves residuals that grow with the distance from the centre and shift their
// mean by little). Each segment has at least `min_segment` rows. Several candidates, each a repair the
// cheap fit scores: an arm whose nominal geometry errs differently
// in two parts of its workspace leaves a step of its own where the poses change region, which a linear
// statistic may rank above a real jump and the fit does not.
std::vector<int> ChangePoints(const std::vector<Eigen::Vector3d>& r, const std::vector<Eigen::Vector3d>& p,
                              size_t min_segment, int count) {
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  const size_t n = r.size();
  if (n < 2 * min_segment) return {};
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& v : p) c += v;
  c /= static_cast<double>(n);
  std::vector<Matrix6> A(n + 1, Matrix6::Zero());  // prefix sums of J^T J and J^T r
  std::vector<Vector6> b(n + 1, Vector6::Zero());
  for (size_t i = 0; i < n; ++i) {
    Eigen::Matrix<double, 3, 6> J;
    J << -Skew(p[i] - c), Eigen::Matrix3d::Identity();
    A[i + 1] = A[i] + J.transpose() * J;
    b[i + 1] = b[i] + J.transpose() * r[i];
  }
  // The part of a segment's squared residuals its own rigid motion explains; a tiny ridge for segments
  // whose points span no volume (a turn about their line is free).
  const auto explained = [](const Matrix6& a, const Vector6& v) {
    const Matrix6 ridge = 1e-9 * (1.0 + a.trace()) * Matrix6::Identity();
    return v.dot((a + ridge).ldlt().solve(v));
  };
  std::vector<std::pair<double, int>> gains;
  for (size_t k = min_segment; k + min_segment <= n; ++k) {
    gains.push_back({explained(A[k], b[k]) + explained(A[n] - A[k], b[n] - b[k]), static_cast<int>(k)});
  }
  std::sort(gains.rbegin(), gains.rend());
  std::vector<int> out;
  for (const auto& [gain, k] : gains) {
    if (static_cast<int>(out.size()) == count) break;
    const bool apart = std::all_of(out.begin(), out.end(), [&, k = k](int o) {
      return static_cast<size_t>(std::abs(o - k)) >= min_segment;
    });
    if (apart) out.push_back(k);
  }
  return out;
}

// Per session, the line from which the measurement frame jumped, if it did: a repair that gives the rows
// from there a frame of their own.
std::vector<Repair> JumpRepairs(const Robot& robot, const Dataset& data, const CheapFit& fit, int jump_candidates) {
  const std::vector<Eigen::Vector3d> r = Residuals(robot, data, fit);
  std::map<int, std::vector<int>> sessions;
  for (size_t i = 0; i < data.rows.size(); ++i) sessions[data.rows[i].session].push_back(static_cast<int>(i));
  int fresh = sessions.rbegin()->first + 1000;
  std::vector<Repair> out;
  for (const auto& [session, rows] : sessions) {
    std::vector<Eigen::Vector3d> rs, ps;
    for (int i : rows) {
      rs.push_back(r[i]);
      ps.push_back(data.rows[i].p);
    }
    for (int k : ChangePoints(rs, ps, std::max<size_t>(5, rs.size() / 20), jump_candidates)) {
      const int line = data.rows[rows[k]].line;
      const int s = session, id = fresh++;
      out.push_back({{"instrument_moved", {}, {line}, "the measurement frame jumped from line " +
                                                           std::to_string(line) +
                                                           ": give the rows from there a session of their own"},
                     [line, s, id](Measurement* m) {
                       if (m->session == s && m->line >= line) m->session = id;
                     }});
    }
  }
  return out;
}

// RMS distance of the measured points to their centroid, m: the scale a fit's RMS is judged against, so
// that a repair that shrinks what is fitted (every joint value divided by 57) cannot look like one.
double Spread(const Dataset& data) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Measurement& m : data.rows) mean += m.p;
  mean /= static_cast<double>(std::max<size_t>(1, data.rows.size()));
  double sum = 0.0;
  for (const Measurement& m : data.rows) sum += (m.p - mean).squaredNorm();
  return std::sqrt(sum / static_cast<double>(std::max<size_t>(1, data.rows.size()))) + 1e-12;
}

// Rows whose joint readings no whole turn brings within the robot file's limits, give or take `slack`;
// 0 when the file gives no limits (the default range is no evidence about the arm).
int RowsOutsideLimits(const Robot& robot, const Dataset& data, double slack) {
  if (robot.limits.empty()) return 0;
  int out = 0;
  for (const Measurement& m : data.rows) {
    Eigen::VectorXd q = m.q;
    if (!WrapIntoLimits(robot, nullptr, q, slack)) ++out;
  }
  return out;
}

// The repairs that fit as well as the best one (within `tie` of its relative score), the best first. Of
// those, only the ones that keep the most rows within the joint limits: a repair that puts the real arm
// where it cannot go is not an equal explanation (a reversed first joint and a second joint's zero half a
// turn off give the same points up to a rigid motion, but the half turn may leave joint 2's range).
// *excluded gets the ties the limits rule out, each with its rows outside them.
std::vector<size_t> Ties(const Robot& robot, const Dataset& sample, const std::vector<Repair>& repairs,
                         const std::vector<double>& relative, const DoctorOptions& o,
                         std::vector<std::pair<size_t, int>>* excluded) {
  std::vector<size_t> tied;
  for (size_t k = 0; k < repairs.size(); ++k) {
    if (relative[k] <= o.tie * *std::min_element(relative.begin(), relative.end())) tied.push_back(k);
  }
  std::sort(tied.begin(), tied.end(), [&](size_t a, size_t b) { return relative[a] < relative[b]; });
  if (tied.size() < 2) return tied;
  // The cheap fit moves a zero by up to max_offset: a reading that far past a limit may still be the arm's.
  std::vector<int> outside;
  for (size_t k : tied) outside.push_back(RowsOutsideLimits(robot, Apply(sample, repairs[k]), o.fit.max_offset));
  const int fewest = *std::min_element(outside.begin(), outside.end());
  std::vector<size_t> kept;
  for (size_t i = 0; i < tied.size(); ++i) {
    if (outside[i] == fewest) {
      kept.push_back(tied[i]);
    } else {
      excluded->push_back({tied[i], outside[i]});
    }
  }
  return kept;
}

// The best repair of one round, or none: each scored by the cheap fit of the repaired sample, relative to
// the spread of its points (a length repair changes both). The margins hold at the repaired data's scale.
bool BestRepair(const Robot& robot, const Dataset& data, const DoctorOptions& o, Finding* found,
                Repair* repair) {
  const Dataset sample = Sample(data, o.max_rows);
  const CheapFit given = FitCheap(robot, sample, o.fit);
  const double given_relative = given.score / Spread(sample);
  std::vector<Repair> repairs = ColumnRepairs(data, StillJoints(data, o.still_range));
  for (Repair& r : JumpRepairs(robot, data, given, o.jump_candidates)) repairs.push_back(std::move(r));
  std::vector<double> relative, scores, spreads;
  for (const Repair& r : repairs) {
    const Dataset repaired = Apply(sample, r);
    spreads.push_back(Spread(repaired));
    scores.push_back(FitCheap(robot, repaired, o.fit).score);
    relative.push_back(scores.back() / spreads.back());
  }
  std::vector<std::pair<size_t, int>> excluded;
  const std::vector<size_t> tied = Ties(robot, sample, repairs, relative, o, &excluded);
  const size_t best = tied.front();
  if (!(relative[best] <= o.ratio * given_relative &&
        (given_relative - relative[best]) * spreads[best] >= o.min_gain)) {
    return false;
  }
  *repair = repairs[best];
  *found = repair->finding;
  found->rms_as_given = given.score;
  found->rms_repaired = scores[best];
  const auto what = [&](size_t k) {
    const std::string& m = repairs[k].finding.message;
    return m.substr(0, m.find(':')) + Format(" (%.3f mm)", scores[k] * 1e3);
  };
  for (size_t i = 1; i < tied.size(); ++i) {
    const Finding& alt = repairs[tied[i]].finding;
    found->alternatives.push_back({alt.cause, alt.joints, scores[tied[i]]});
    found->message += "; these data cannot tell it from: " + what(tied[i]);
  }
  for (const auto& [k, outside] : excluded) {
    found->message += "; fits as well but puts " + std::to_string(outside) + " of " +
                      std::to_string(sample.rows.size()) + " rows outside the joint limits: " + what(k);
  }
  return true;
}

}  // namespace

std::vector<Finding> Diagnose(const Robot& robot, const Dataset& data, const DoctorOptions& options) {
  std::vector<Finding> findings;
  // The causes are read off tracker points against the arm's prediction. Rows of the other instruments
  // (distances, contacts, partial points) each carry too little of a point to tell a cause, and are left
  // to the fit; with fewer than a dozen points there is nothing to check.
  std::vector<int> points;
  for (size_t i = 0; i < data.rows.size(); ++i) {
    if (data.rows[i].IsFullPoint()) points.push_back(static_cast<int>(i));
  }
  if (points.size() < 12) return findings;
  Dataset current = data;
  for (size_t i = 0; i < current.rows.size(); ++i) {  // rows made in memory: their index stands for the line
    if (current.rows[i].line <= 0) current.rows[i].line = static_cast<int>(i + 1);
  }
  if (points.size() < current.rows.size()) current = current.SelectRows(points);
  for (int round = 0; round < options.rounds; ++round) {
    Finding f;
    Repair r;
    if (!BestRepair(robot, current, options, &f, &r)) break;
    findings.push_back(f);
    current = Apply(current, r);
  }
  for (Finding& f : CheckTool(robot, current, options)) findings.push_back(f);
  for (Finding& f : CheckOutliers(robot, current, options)) findings.push_back(f);
  for (Finding& f : CheckStill(robot, current, options)) findings.push_back(f);
  return findings;
}

double RmsAsGiven(const Robot& robot, const Dataset& data, const DoctorOptions& options) {
  return data.rows.empty() ? 0.0 : FitCheap(robot, Sample(data, options.max_rows), options.fit).score;
}

}  // namespace kincal::doctor
