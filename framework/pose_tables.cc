#include "framework/pose_tables.h"

#include <cmath>
#include <optional>

#include "framework/atomic_file.h"
#include "framework/error.h"

namespace kincal {
namespace {

struct TableRow {
  int line = 0;
  std::vector<double> values;
};

// Rows of numbers separated by blanks (or commas); empty lines and '#' lines are skipped.
std::vector<TableRow> ReadTable(const std::string& path, size_t columns) {
  const std::string text = ReadFileToString(path);
  std::vector<TableRow> rows;
  size_t start = 0;
  int line = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line;
    const std::string s = text.substr(start, end - start);
    start = end + 1;
    TableRow row;
    row.line = line;
    size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == ',')) ++i;
      if (i >= s.size() || s[i] == '#') break;
      size_t j = i;
      while (j < s.size() && !(s[j] == ' ' || s[j] == '\t' || s[j] == '\r' || s[j] == ',')) ++j;
      double v = 0.0;
      if (!ParseDouble(s.substr(i, j - i), &v) || !std::isfinite(v)) {
        ThrowInputError(path, line, static_cast<int>(i) + 1,
                        "expected a finite number, got '" + s.substr(i, j - i) + "'");
      }
      row.values.push_back(v);
      i = j;
    }
    if (row.values.empty()) continue;
    if (row.values.size() != columns) {
      ThrowInputError(path, line, 1,
                      "expected " + std::to_string(columns) + " numbers, got " + std::to_string(row.values.size()));
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) ThrowInputError(path, line, 1, "expected at least one row of numbers");
  return rows;
}

bool SamePose(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
  for (size_t j = 0; j < a.size(); ++j) {
    if (!(std::abs(a[j] - b[j]) <= tolerance)) return false;
  }
  return true;
}

// Where each pose of `joints` is in `sequence` (match) and the index there of its previous pose
// (previous, -1 for none).
struct SequencePlaces {
  std::vector<int> match, previous;
};

SequencePlaces PlaceInSequence(const std::vector<TableRow>& joints, const std::string& joints_path,
                               const std::vector<TableRow>& sequence, const std::string& sequence_path) {
  // The tables hold the same readings, perhaps printed with fewer digits: 1e-6 of the unit tells them
  // apart from any other pose.
  constexpr double kTolerance = 1e-6;
  SequencePlaces out;
  size_t next = 0;  // first sequence row the next pose may match
  for (size_t i = 0; i < joints.size(); ++i) {
    size_t s = next;
    while (s < sequence.size() && !SamePose(joints[i].values, sequence[s].values, kTolerance)) ++s;
    if (s == sequence.size()) {
      ThrowInputError(joints_path, joints[i].line, 1,
                      "this pose is not in the sequence " + sequence_path +
                          (i == 0 ? std::string() : " after its line " + std::to_string(sequence[next - 1].line)) +
                          " (the joints table must be the sequence with rows removed, in order)");
    }
    int p = static_cast<int>(s) - 1;
    while (p >= 0 && SamePose(sequence[static_cast<size_t>(p)].values, sequence[s].values, 0.0)) --p;
    out.match.push_back(static_cast<int>(s));
    out.previous.push_back(p);
    next = s + 1;
  }
  return out;
}

}  // namespace

Dataset ReadPoseTables(const PoseTables& tables, int dof) {
  if (tables.positions.empty()) ThrowInputError(tables.joints, 0, 0, "no marker position table given");
  const std::vector<TableRow> joints = ReadTable(tables.joints, static_cast<size_t>(dof));
  std::vector<std::vector<TableRow>> points;
  for (const auto& [marker, path] : tables.positions) {
    points.push_back(ReadTable(path, 3));
    if (points.back().size() != joints.size()) {
      ThrowInputError(path, points.back().back().line, 1,
                      "expected " + std::to_string(joints.size()) + " rows, as in " + tables.joints + ", got " +
                          std::to_string(points.back().size()));
    }
  }
  SequencePlaces places;
  std::vector<TableRow> sequence;
  if (!tables.sequence.empty()) {
    sequence = ReadTable(tables.sequence, static_cast<size_t>(dof));
    places = PlaceInSequence(joints, tables.joints, sequence, tables.sequence);
  }
  Dataset data;
  data.dof = dof;
  data.source = tables.joints;
  data.length_unit = tables.length_unit;
  data.angle_unit = tables.angle_unit;
  for (size_t i = 0; i < joints.size(); ++i) {
    Eigen::VectorXd q(dof);
    for (int j = 0; j < dof; ++j) q[j] = joints[i].values[j] * tables.angle_unit.to_si;
    // The previous pose from the sequence, unless the row order gives it (Dataset::PreviousPoses: the
    // pose before, when its joint values differ).
    std::optional<Eigen::VectorXd> from_q;
    if (!places.previous.empty() && places.previous[i] >= 0) {
      const TableRow& from = sequence[static_cast<size_t>(places.previous[i])];
      const bool row_order_gives_it =
          i > 0 && SamePose(from.values, sequence[static_cast<size_t>(places.match[i - 1])].values, 0.0) &&
          !SamePose(joints[i].values, joints[i - 1].values, 0.0);
      if (!row_order_gives_it) {
        from_q = Eigen::VectorXd(dof);
        for (int j = 0; j < dof; ++j) (*from_q)[j] = from.values[j] * tables.angle_unit.to_si;
      }
    }
    for (size_t k = 0; k < points.size(); ++k) {
      Measurement m;
      m.q = q;
      const auto& p = points[k][i].values;
      m.p = Eigen::Vector3d(p[0], p[1], p[2]) * tables.length_unit.to_si;
      m.marker = tables.positions[k].first;
      m.from_q = from_q;
      m.line = joints[i].line;
      data.rows.push_back(std::move(m));
    }
  }
  return data;
}

}  // namespace kincal
