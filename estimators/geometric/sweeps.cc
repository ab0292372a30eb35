#include "estimators/geometric/sweeps.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include "framework/error.h"
#include "framework/prediction.h"

namespace kincal::geometric {
namespace {

// Commanded angles written to a file and read back are equal to far better than this.
constexpr double kHeldTolerance = 1e-9;

std::string RowName(const Dataset& data, int row) {
  const int line = data.rows[row].line;
  return line > 0 ? data.source + ":" + std::to_string(line) : "row " + std::to_string(row + 1);
}

}  // namespace

std::string SweepSet::Where(int joint, const std::string& source) const {
  const Sweep& s = sweeps[joint - 1];
  if (s.first_line > 0) {
    return "sweep of joint " + std::to_string(joint) + " (" + source + " lines " + std::to_string(s.first_line) + "-" +
           std::to_string(s.last_line) + ")";
  }
  return "sweep of joint " + std::to_string(joint) + " (rows " + std::to_string(s.first_row + 1) + "-" +
         std::to_string(s.last_row + 1) + ")";
}

SweepSet ExtractSweeps(const Robot& controller, const Robot& start, const Dataset& data, const std::string& marker,
                       const std::string& who) {
  const int n = start.dof();
  SweepSet set;
  set.dof = n;
  set.sweeps.assign(n, Sweep());

  std::set<std::string> markers;
  for (const auto& m : data.rows) {
    if (m.sweep > 0) markers.insert(m.marker);
    else ++set.free_rows;
  }
  if (markers.empty()) {
    ThrowInputError(data.source, 0, 0, who + ": the dataset has no sweep rows (a `sweep` column naming the joint "
                                             "swept at each stop is needed)");
  }
  if (!marker.empty()) {
    if (!markers.count(marker)) ThrowInputError(data.source, 0, 0, who + ": no sweep rows of marker '" + marker + "'");
    set.marker = marker;
  } else if (markers.size() > 1) {
    std::string list;
    for (const auto& id : markers) list += (list.empty() ? "" : ", ") + (id.empty() ? std::string("(none)") : id);
    ThrowInputError(data.source, 0, 0, who + ": the sweeps record several markers (" + list +
                                           "); choose one with the option `marker`");
  } else {
    set.marker = *markers.begin();
  }
  start.MarkerPosition(set.marker);  // throws for a marker the robot does not list

  std::vector<Eigen::VectorXd> held_q(n);  // commanded configuration at each sweep's first row
  std::vector<Eigen::VectorXd> sum_x(n);
  bool have_cal = false;
  for (int r = 0; r < static_cast<int>(data.rows.size()); ++r) {
    const Measurement& m = data.rows[r];
    if (m.sweep <= 0 || m.marker != set.marker) continue;
    const int j = m.sweep;
    if (j > n) ThrowInputError(RowName(data, r) + ": " + who + ": sweep index " + std::to_string(j) + " out of range 1.." + std::to_string(n));
    const Eigen::VectorXd x = DriveAngles(controller, start, m);
    if (!have_cal) {
      have_cal = true;
      set.q_cal = m.q;
      set.x_cal = x;
      set.cal_row = r;
      set.session = m.session;
    }
    if (m.session != set.session) {
      ThrowInputError(RowName(data, r) + ": " + who + ": the sweeps come from several instrument sessions (" +
                      std::to_string(set.session) + " and " + std::to_string(m.session) + "); give one session's sweeps");
    }
    Sweep& s = set.sweeps[j - 1];
    if (s.joint == 0) {
      s.joint = j;
      s.first_row = r;
      s.first_line = m.line;
      held_q[j - 1] = m.q;
      sum_x[j - 1] = Eigen::VectorXd::Zero(n);
      set.order.push_back(j);
    }
    for (int i = 0; i < n; ++i) {
      if (i != j - 1 && std::abs(m.q[i] - held_q[j - 1][i]) > kHeldTolerance) {
        ThrowInputError(RowName(data, r) + ": " + who + ": joint " + std::to_string(i + 1) + " moves during the sweep of joint " +
                        std::to_string(j) + " (a sweep turns one joint; the others hold)");
      }
    }
    s.points.push_back(m.p);
    s.x.push_back(x[j - 1]);
    sum_x[j - 1] += x;
    s.last_row = r;
    s.last_line = m.line;
  }
  for (int j = 1; j <= n; ++j) {
    Sweep& s = set.sweeps[j - 1];
    if (s.joint == 0) continue;
    // Held joints' drive variables are averaged over the sweep: real encoders of a held joint can jitter.
    const Eigen::VectorXd x_held = sum_x[j - 1] / static_cast<double>(s.points.size());
    for (int i = 0; i < j - 1; ++i) {
      if (std::abs(held_q[j - 1][i] - set.q_cal[i]) > kHeldTolerance) s.moved.emplace_back(i, x_held[i] - set.x_cal[i]);
    }
  }
  return set;
}

}  // namespace kincal::geometric
