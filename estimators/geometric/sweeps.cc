#include "estimators/geometric/sweeps.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "framework/error.h"
#include "robot/prediction.h"

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
                       const std::string& who, bool several_markers) {
  const int n = start.dof();
  SweepSet set;
  set.dof = n;
  set.sweeps.assign(n, Sweep());

  std::vector<std::string> markers;  // in order of first appearance
  for (const auto& m : data.rows) {
    if (m.sweep <= 0)
      ++set.free_rows;
    else if (std::find(markers.begin(), markers.end(), m.marker) == markers.end())
      markers.push_back(m.marker);
  }
  if (markers.empty()) {
    ThrowInputError(data.source, 0, 0,
                    who +
                        ": the dataset has no sweep rows (a `sweep` column naming the joint "
                        "swept at each stop is needed)");
  }
  if (!marker.empty()) {
    if (std::find(markers.begin(), markers.end(), marker) == markers.end()) {
      ThrowInputError(data.source, 0, 0, who + ": no sweep rows of marker '" + marker + "'");
    }
    set.markers = {marker};
  } else if (markers.size() > 1 && !several_markers) {
    std::set<std::string> sorted(markers.begin(), markers.end());
    std::string list;
    for (const auto& id : sorted) list += (list.empty() ? "" : ", ") + (id.empty() ? std::string("(none)") : id);
    ThrowInputError(data.source, 0, 0,
                    who + ": the sweeps record several markers (" + list + "); choose one with the option `marker`");
  } else {
    set.markers = markers;
  }
  set.marker = set.markers[0];
  for (const auto& id : set.markers) start.MarkerPosition(id);  // throws for a marker the robot does not list
  const int M = static_cast<int>(set.markers.size());
  const auto marker_index = [&](const std::string& id) {
    return static_cast<int>(std::find(set.markers.begin(), set.markers.end(), id) - set.markers.begin());
  };
  // The physical joints the readings command (the coupling; identity without one).
  const auto coupled = [&](const Eigen::VectorXd& q) -> Eigen::VectorXd {
    return start.coupling.size() == 0 ? q : Eigen::VectorXd(start.coupling * q);
  };

  std::vector<Eigen::VectorXd> held_q(n);  // coupled commanded configuration at each sweep's first row
  std::vector<Eigen::VectorXd> sum_x(n);
  // Per sweep: the readings of each stop (from the first marker's rows) and each marker's row count.
  std::vector<std::vector<Eigen::VectorXd>> stop_q(n);
  std::vector<std::vector<int>> count(n, std::vector<int>(M, 0));
  bool have_cal = false;
  for (int r = 0; r < static_cast<int>(data.rows.size()); ++r) {
    const Measurement& m = data.rows[r];
    const int mi = marker_index(m.marker);
    if (m.sweep <= 0 || mi == M) continue;
    const int j = m.sweep;
    if (j > n)
      ThrowInputError(RowName(data, r) + ": " + who + ": sweep index " + std::to_string(j) + " out of range 1.." +
                      std::to_string(n));
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
                      std::to_string(set.session) + " and " + std::to_string(m.session) +
                      "); give one session's sweeps");
    }
    Sweep& s = set.sweeps[j - 1];
    if (s.joint == 0) {
      s.joint = j;
      s.first_row = r;
      s.first_line = m.line;
      held_q[j - 1] = coupled(m.q);
      sum_x[j - 1] = Eigen::VectorXd::Zero(n);
      s.marker_points.assign(M, {});
      set.order.push_back(j);
    }
    const Eigen::VectorXd q = coupled(m.q);
    for (int i = 0; i < n; ++i) {
      if (i != j - 1 && std::abs(q[i] - held_q[j - 1][i]) > kHeldTolerance) {
        ThrowInputError(RowName(data, r) + ": " + who + ": joint " + std::to_string(i + 1) +
                        " moves during the sweep of joint " + std::to_string(j) +
                        " (a sweep turns one joint; the others hold)");
      }
    }
    const int k = count[j - 1][mi]++;  // this row is stop k of its marker
    if (k == static_cast<int>(stop_q[j - 1].size())) {
      stop_q[j - 1].push_back(m.q);
      s.x.push_back(x[j - 1]);
      sum_x[j - 1] += x;
    } else if ((m.q - stop_q[j - 1][k]).cwiseAbs().maxCoeff() > kHeldTolerance) {
      ThrowInputError(RowName(data, r) + ": " + who + ": marker '" + m.marker + "' at stop " + std::to_string(k + 1) +
                      " of the sweep of joint " + std::to_string(j) +
                      " has other joint values than the first marker measured there (every marker is measured at "
                      "every stop, in the same order)");
    }
    s.marker_points[mi].push_back(m.p);
    s.last_row = r;
    s.last_line = m.line;
  }
  for (int j = 1; j <= n; ++j) {
    Sweep& s = set.sweeps[j - 1];
    if (s.joint == 0) continue;
    for (int mi = 0; mi < M; ++mi) {
      if (s.marker_points[mi].size() != s.x.size()) {
        ThrowInputError(data.source, 0, 0,
                        who + ": " + set.Where(j, data.source) + ": marker '" + set.markers[mi] + "' is measured at " +
                            std::to_string(s.marker_points[mi].size()) + " of its " + std::to_string(s.x.size()) +
                            " stops (every marker is needed at every stop)");
      }
    }
    s.points = s.marker_points[0];
    // Held joints' drive variables are averaged over the sweep: real encoders of a held joint can jitter.
    const Eigen::VectorXd x_held = sum_x[j - 1] / static_cast<double>(s.x.size());
    const Eigen::VectorXd q_cal = coupled(set.q_cal);
    for (int i = 0; i < j - 1; ++i) {
      if (std::abs(held_q[j - 1][i] - q_cal[i]) > kHeldTolerance) s.moved.emplace_back(i, x_held[i] - set.x_cal[i]);
    }
  }
  return set;
}

}  // namespace kincal::geometric
