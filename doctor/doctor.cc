#include "doctor/doctor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

#include "doctor/checks.h"

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

// The row (index into `rows`) from which the mean residual shifts most: a mean-shift change point of the
// 3-D residuals, each segment at least `min_segment` rows.
int ChangePoint(const std::vector<Eigen::Vector3d>& r, size_t min_segment) {
  const size_t n = r.size();
  if (n < 2 * min_segment) return -1;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const auto& v : r) total += v;
  Eigen::Vector3d left = Eigen::Vector3d::Zero();
  double best = 0.0;
  int at = -1;
  for (size_t k = 1; k < n; ++k) {
    left += r[k - 1];
    if (k < min_segment || n - k < min_segment) continue;
    const double gain = left.squaredNorm() / k + (total - left).squaredNorm() / (n - k);
    if (gain > best) {
      best = gain;
      at = static_cast<int>(k);
    }
  }
  return at;
}

// Per session, the line from which the measurement frame jumped, if it did: a repair that gives the rows
// from there a frame of their own.
std::vector<Repair> JumpRepairs(const Robot& robot, const Dataset& data, const CheapFit& fit) {
  const std::vector<Eigen::Vector3d> r = Residuals(robot, data, fit);
  std::map<int, std::vector<int>> sessions;
  for (size_t i = 0; i < data.rows.size(); ++i) sessions[data.rows[i].session].push_back(static_cast<int>(i));
  int fresh = sessions.rbegin()->first + 1000;
  std::vector<Repair> out;
  for (const auto& [session, rows] : sessions) {
    std::vector<Eigen::Vector3d> rs;
    for (int i : rows) rs.push_back(r[i]);
    const int k = ChangePoint(rs, std::max<size_t>(5, rs.size() / 20));
    if (k < 0) continue;
    const int line = data.rows[rows[k]].line;
    const int s = session, id = fresh++;
    out.push_back({{"instrument_moved", {}, {line}, "the measurement frame jumped from line " +
                                                         std::to_string(line) +
                                                         ": give the rows from there a session of their own"},
                   [line, s, id](Measurement* m) {
                     if (m->session == s && m->line >= line) m->session = id;
                   }});
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

// The best repair of one round, or none: each scored by the cheap fit of the repaired sample, relative to
// the spread of its points (a length repair changes both). The margins hold at the repaired data's scale.
bool BestRepair(const Robot& robot, const Dataset& data, const DoctorOptions& o, Finding* found,
                Repair* repair) {
  const Dataset sample = Sample(data, o.max_rows);
  const CheapFit given = FitCheap(robot, sample, o.fit);
  const double given_relative = given.score / Spread(sample);
  std::vector<Repair> repairs = ColumnRepairs(data, StillJoints(data, o.still_range));
  for (Repair& r : JumpRepairs(robot, data, given)) repairs.push_back(std::move(r));
  std::vector<double> relative, scores, spreads;
  for (const Repair& r : repairs) {
    const Dataset repaired = Apply(sample, r);
    spreads.push_back(Spread(repaired));
    scores.push_back(FitCheap(robot, repaired, o.fit).score);
    relative.push_back(scores.back() / spreads.back());
  }
  const size_t best = std::min_element(relative.begin(), relative.end()) - relative.begin();
  if (!(relative[best] <= o.ratio * given_relative &&
        (given_relative - relative[best]) * spreads[best] >= o.min_gain)) {
    return false;
  }
  *repair = repairs[best];
  *found = repair->finding;
  found->rms_as_given = given.score;
  found->rms_repaired = scores[best];
  for (size_t k = 0; k < repairs.size(); ++k) {
    if (k == best || relative[k] > o.tie * relative[best]) continue;
    const Finding& alt = repairs[k].finding;
    found->alternatives.push_back({alt.cause, alt.joints});
    found->message += "; as well: " + alt.message.substr(0, alt.message.find(':'));
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
