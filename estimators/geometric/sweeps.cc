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

namespace {

// The markers the sweep rows use, in order of first appearance (into set->markers), and the rows
// without a sweep (set->free_rows).
void ChooseMarkers(const Dataset& data, const std::string& marker, const std::string& who, bool several_markers,
                   SweepSet* set) {
  std::vector<std::string> markers;  // in order of first appearance
  for (const auto& m : data.rows) {
    if (m.sweep <= 0)
      ++set->free_rows;
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
    set->markers = {marker};
  } else if (markers.size() > 1 && !several_markers) {
    std::set<std::string> sorted(markers.begin(), markers.end());
    std::string list;
    for (const auto& id : sorted) list += (list.empty() ? "" : ", ") + (id.empty() ? std::string("(none)") : id);
    ThrowInputError(data.source, 0, 0,
                    who + ": the sweeps record several markers (" + list + "); choose one with the option `marker`");
  } else {
    set->markers = markers;
  }
  set->marker = set->markers[0];
}

// The sweep rows, one at a time, into a SweepSet, with what the checks across rows need.
class SweepCollector {
 public:
  SweepCollector(const Robot& controller, const Robot& start, const Dataset& data, const std::string& who,
                 SweepSet* set)
      : controller_(controller),
        start_(start),
        data_(data),
        who_(who),
        set_(*set),
        n_(set->dof),
        M_(static_cast<int>(set->markers.size())),
        held_q_(n_),
        sum_x_(n_),
        stop_q_(n_),
        count_(n_, std::vector<int>(M_, 0)) {}

  void Add(int r) {
    const Measurement& m = data_.rows[r];
    const int mi = MarkerIndex(m.marker);
    if (m.sweep <= 0 || mi == M_) return;
    const int j = m.sweep;
    if (j > n_)
      ThrowInputError(RowName(data_, r) + ": " + who_ + ": sweep index " + std::to_string(j) + " out of range 1.." +
                      std::to_string(n_));
    const Eigen::VectorXd x = DriveAngles(controller_, start_, m);
    if (!have_cal_) {
      have_cal_ = true;
      set_.q_cal = m.q;
      set_.x_cal = x;
      set_.cal_row = r;
      set_.session = m.session;
    }
    if (m.session != set_.session) {
      ThrowInputError(RowName(data_, r) + ": " + who_ + ": the sweeps come from several instrument sessions (" +
                      std::to_string(set_.session) + " and " + std::to_string(m.session) +
                      "); give one session's sweeps");
    }
    Sweep& s = set_.sweeps[j - 1];
    if (s.joint == 0) {
      s.joint = j;
      s.first_row = r;
      s.first_line = m.line;
      held_q_[j - 1] = Coupled(m.q);
      sum_x_[j - 1] = Eigen::VectorXd::Zero(n_);
      s.marker_points.assign(M_, {});
      set_.order.push_back(j);
    }
    CheckHeld(r, j);
    const int k = count_[j - 1][mi]++;  // this row is stop k of its marker
    if (k == static_cast<int>(stop_q_[j - 1].size())) {
      stop_q_[j - 1].push_back(m.q);
      s.x.push_back(x[j - 1]);
      sum_x_[j - 1] += x;
    } else if ((m.q - stop_q_[j - 1][k]).cwiseAbs().maxCoeff() > kHeldTolerance) {
      ThrowInputError(RowName(data_, r) + ": " + who_ + ": marker '" + m.marker + "' at stop " + std::to_string(k + 1) +
                      " of the sweep of joint " + std::to_string(j) +
                      " has other joint values than the first marker measured there (every marker is measured at "
                      "every stop, in the same order)");
    }
    s.marker_points[mi].push_back(m.p);
    s.last_row = r;
    s.last_line = m.line;
  }

  // Every marker at every stop; the first marker's points; the proximal joints moved during each sweep.
  void Finish() {
    for (int j = 1; j <= n_; ++j) {
      Sweep& s = set_.sweeps[j - 1];
      if (s.joint == 0) continue;
      for (int mi = 0; mi < M_; ++mi) {
        if (s.marker_points[mi].size() != s.x.size()) {
          ThrowInputError(data_.source, 0, 0,
                          who_ + ": " + set_.Where(j, data_.source) + ": marker '" + set_.markers[mi] +
                              "' is measured at " + std::to_string(s.marker_points[mi].size()) + " of its " +
                              std::to_string(s.x.size()) + " stops (every marker is needed at every stop)");
        }
      }
      s.points = s.marker_points[0];
      // Held joints' drive variables are averaged over the sweep: real encoders of a held joint can jitter.
      const Eigen::VectorXd x_held = sum_x_[j - 1] / static_cast<double>(s.x.size());
      const Eigen::VectorXd q_cal = Coupled(set_.q_cal);
      for (int i = 0; i < j - 1; ++i) {
        if (std::abs(held_q_[j - 1][i] - q_cal[i]) > kHeldTolerance) s.moved.emplace_back(i, x_held[i] - set_.x_cal[i]);
      }
    }
  }

 private:
  int MarkerIndex(const std::string& id) const {
    return static_cast<int>(std::find(set_.markers.begin(), set_.markers.end(), id) - set_.markers.begin());
  }
  // The physical joints the readings command (the coupling; identity without one).
  Eigen::VectorXd Coupled(const Eigen::VectorXd& q) const {
    return start_.coupling.size() == 0 ? q : Eigen::VectorXd(start_.coupling * q);
  }
  // Row r of joint j's sweep holds every other joint where the sweep's first row has it.
  void CheckHeld(int r, int j) const {
    const Eigen::VectorXd q = Coupled(data_.rows[r].q);
    for (int i = 0; i < n_; ++i) {
      if (i != j - 1 && std::abs(q[i] - held_q_[j - 1][i]) > kHeldTolerance) {
        ThrowInputError(RowName(data_, r) + ": " + who_ + ": joint " + std::to_string(i + 1) +
                        " moves during the sweep of joint " + std::to_string(j) +
                        " (a sweep turns one joint; the others hold)");
      }
    }
  }

  const Robot& controller_;
  const Robot& start_;
  const Dataset& data_;
  const std::string& who_;
  SweepSet& set_;
  const int n_, M_;
  std::vector<Eigen::VectorXd> held_q_;  // coupled commanded configuration at each sweep's first row
  std::vector<Eigen::VectorXd> sum_x_;
  // Per sweep: the readings of each stop (from the first marker's rows) and each marker's row count.
  std::vector<std::vector<Eigen::VectorXd>> stop_q_;
  std::vector<std::vector<int>> count_;
  bool have_cal_ = false;
};

}  // namespace

SweepSet ExtractSweeps(const Robot& controller, const Robot& start, const Dataset& data, const std::string& marker,
                       const std::string& who, bool several_markers) {
  SweepSet set;
  set.dof = start.dof();
  set.sweeps.assign(set.dof, Sweep());
  ChooseMarkers(data, marker, who, several_markers, &set);
  for (const auto& id : set.markers) start.MarkerPosition(id);  // throws for a marker the robot does not list
  SweepCollector collector(controller, start, data, who, &set);
  for (int r = 0; r < static_cast<int>(data.rows.size()); ++r) collector.Add(r);
  collector.Finish();
  return set;
}

}  // namespace kincal::geometric
