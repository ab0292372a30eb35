#include "doctor/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kincal::doctor {
namespace {

constexpr double kMm = 1e3;

bool ClearlyBetter(double given, double repaired, const DoctorOptions& o) {
  return repaired <= o.ratio * given && given - repaired >= o.min_gain;
}

}  // namespace

Dataset Sample(const Dataset& data, int max_rows) {
  const size_t n = data.rows.size();
  if (n <= static_cast<size_t>(max_rows)) return data;
  std::vector<int> keep;
  for (int k = 0; k < max_rows; ++k) keep.push_back(static_cast<int>(k * n / static_cast<size_t>(max_rows)));
  return data.SelectRows(keep);
}

std::set<int> StillJoints(const Dataset& data, double range) {
  std::set<int> out;
  for (int j = 0; j < data.dof; ++j) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Measurement& m : data.rows) {
      lo = std::min(lo, m.q[j]);
      hi = std::max(hi, m.q[j]);
    }
    if (hi - lo < range) out.insert(j);
  }
  return out;
}

// The markers the robot file places away from the flange (a file that leaves the tool at the flange says
// it does not know where the reflector is: nothing to compare with), fitted far from where it says.
std::vector<Finding> CheckTool(const Robot& robot, const Dataset& data, const DoctorOptions& o) {
  const Dataset sample = Sample(data, o.max_rows);
  const CheapFit free = FitCheap(robot, sample, o.fit);
  std::string message;
  for (const auto& [id, fitted] : free.markers) {
    const Eigen::Vector3d file = robot.MarkerPosition(id);
    if ((robot.model().tool() * file).norm() < 1e-3) continue;
    const double d = (fitted - file).norm();
    if (d <= o.tool_distance) continue;
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "%s fits %.1f mm from where the robot file puts it, at (%.1f, %.1f, %.1f) mm",
                  id.empty() ? "the tool origin" : ("marker " + id).c_str(), d * kMm, fitted.x() * kMm,
                  fitted.y() * kMm, fitted.z() * kMm);
    message += (message.empty() ? "" : "; ") + std::string(buffer);
  }
  if (message.empty()) return {};
  CheapFitOptions held = o.fit;
  held.free_markers = false;
  const double given = FitCheap(robot, sample, held).score;
  if (!ClearlyBetter(given, free.score, o)) return {};
  Finding f{"tool", {}, {}, message + " in the tool frame: correct the robot file's tool or markers", given,
            free.score, {}};
  return {f};
}

// Rows whose residual under the cheap fit exceeds outlier_factor times the median and outlier_floor.
std::vector<Finding> CheckOutliers(const Robot& robot, const Dataset& data, const DoctorOptions& o) {
  const CheapFit fit = FitCheap(robot, Sample(data, o.max_rows), o.fit);
  const std::vector<Eigen::Vector3d> r = Residuals(robot, data, fit);
  std::vector<double> norms;
  for (const auto& v : r) norms.push_back(v.norm());
  const double threshold = std::max(o.outlier_factor * Median(norms), o.outlier_floor);
  std::vector<int> keep, lines;
  for (size_t i = 0; i < norms.size(); ++i) {
    if (norms[i] > threshold) {
      lines.push_back(data.rows[i].line);
    } else {
      keep.push_back(static_cast<int>(i));
    }
  }
  if (lines.empty() || lines.size() * 5 > norms.size()) return {};
  const Dataset kept = data.SelectRows(keep);
  const double repaired = TrimmedRms(Residuals(robot, kept, FitCheap(robot, Sample(kept, o.max_rows), o.fit)), 1.0);
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "%zu rows lie more than %.1f mm (%.0f x the median) from the fit: remove or re-measure them",
                lines.size(), threshold * kMm, o.outlier_factor);
  return {{"outliers", {}, lines, buffer, TrimmedRms(r, 1.0), repaired, {}}};
}

std::vector<Finding> CheckStill(const Robot& robot, const Dataset& data, const DoctorOptions& o) {
  const std::set<int> still = StillJoints(data, o.still_range);
  if (still.empty()) return {};
  const double score = FitCheap(robot, Sample(data, o.max_rows), o.fit).score;
  std::vector<Finding> out;
  for (int j : still) {
    out.push_back({"joint_not_moved", {j + 1}, {}, "joint " + std::to_string(j + 1) +
                       " never moved (its values span less than " + std::to_string(o.still_range * 180 / M_PI).substr(0, 4) +
                       " deg): its parameters cannot be identified from these data; move it",
                   score, score, {}});
  }
  return out;
}

const OptionTable<DoctorOptions>& DoctorOptions::Table() {
  using O = DoctorOptions;
  static const OptionTable<O> table =
      OptionTable<O>("check")
          .Add("ratio", &O::ratio, "a repair is a finding when it divides the cheap fit's trimmed RMS by 1/ratio at least",
               Between(0.0, 1.0, true, false))
          .Add("min_gain", OptionUnit::kLength, &O::min_gain, "... and lowers it by this much at least", NonNegative())
          .Add("tool_distance", OptionUnit::kLength, &O::tool_distance,
               "a marker fitted this far from the robot file's is the wrong tool", Positive())
          .Add("outlier_factor", &O::outlier_factor, "an outlier's residual exceeds this many times the median", Positive())
          .Add("outlier_floor", OptionUnit::kLength, &O::outlier_floor, "... and this length", NonNegative())
          .Add("still_range", OptionUnit::kAngleDeg, &O::still_range, "a joint whose values span less never moved",
               Positive())
          .Add("tie", &O::tie, "repairs within this factor of the best one's RMS are named as alternatives",
               Between(1.0, 2.0, false, false))
          .Add("max_rows", &O::max_rows, "rows the hypotheses are fitted on (evenly spaced) in larger files", AtLeast(20))
          .Add("jump_candidates", &O::jump_candidates,
               "change points per session (the likeliest, far apart) scored as repairs of a jumped frame", AtLeast(1))
          .Add("rounds", &O::rounds, "repairs found one after the other, each on the data repaired so far", AtLeast(1));
  return table;
}

nlohmann::json FindingsToJson(const std::vector<Finding>& findings, double rms_as_given) {
  nlohmann::json out = {{"rms_as_given_mm", rms_as_given * kMm}, {"findings", nlohmann::json::array()}};
  for (const Finding& f : findings) {
    nlohmann::json alternatives = nlohmann::json::array();
    for (const auto& a : f.alternatives) {
      alternatives.push_back({{"cause", a.cause}, {"joints", a.joints}, {"rms_repaired_mm", a.rms_repaired * kMm}});
    }
    out["findings"].push_back({{"cause", f.cause},
                               {"alternatives", alternatives},
                               {"joints", f.joints},
                               {"lines", f.lines},
                               {"message", f.message},
                               {"rms_as_given_mm", f.rms_as_given * kMm},
                               {"rms_repaired_mm", f.rms_repaired * kMm}});
  }
  return out;
}

std::string FindingLine(const Finding& f) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, " (fit RMS %.3f mm as given, %.3f mm repaired)", f.rms_as_given * kMm,
                f.rms_repaired * kMm);
  return "check: " + f.cause + ": " + f.message + buffer;
}

}  // namespace kincal::doctor
