#include "framework/pose_tables.h"

#include <cmath>

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
        ThrowInputError(path, line, static_cast<int>(i) + 1, "expected a finite number, got '" + s.substr(i, j - i) + "'");
      }
      row.values.push_back(v);
      i = j;
    }
    if (row.values.empty()) continue;
    if (row.values.size() != columns) {
      ThrowInputError(path, line, 1, "expected " + std::to_string(columns) + " numbers, got " +
                                         std::to_string(row.values.size()));
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) ThrowInputError(path, line, 1, "expected at least one row of numbers");
  return rows;
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
  Dataset data;
  data.dof = dof;
  data.source = tables.joints;
  data.length_unit = tables.length_unit;
  data.angle_unit = tables.angle_unit;
  for (size_t i = 0; i < joints.size(); ++i) {
    Eigen::VectorXd q(dof);
    for (int j = 0; j < dof; ++j) q[j] = joints[i].values[j] * tables.angle_unit.to_si;
    for (size_t k = 0; k < points.size(); ++k) {
      Measurement m;
      m.q = q;
      const auto& p = points[k][i].values;
      m.p = Eigen::Vector3d(p[0], p[1], p[2]) * tables.length_unit.to_si;
      m.marker = tables.positions[k].first;
      m.line = joints[i].line;
      data.rows.push_back(std::move(m));
    }
  }
  return data;
}

}  // namespace kincal
