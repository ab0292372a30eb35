#include "framework/dataset.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "framework/atomic_file.h"
#include "framework/csv.h"
#include "framework/error.h"
#include "framework/memory.h"

namespace kincal {

std::string MeasurementKindName(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::kPoint:
      return "point";
    case MeasurementKind::kDistance:
      return "distance";
    case MeasurementKind::kPlane:
      return "plane";
    case MeasurementKind::kFixedPoint:
      return "fixed_point";
  }
  return "point";
}

std::string Measurement::Description() const {
  switch (kind) {
    case MeasurementKind::kPoint:
      return IsFullPoint() ? "a point" : "a partial point";
    case MeasurementKind::kDistance:
      return "a distance";
    case MeasurementKind::kPlane:
      return "a plane contact";
    case MeasurementKind::kFixedPoint:
      return "a fixed point";
  }
  return "a point";
}

bool Dataset::HasEncoders() const { return !rows.empty() && !rows.front().encoders.empty(); }
bool Dataset::HasOrientation() const {
  for (const auto& r : rows)
    if (r.orientation) return true;
  return false;
}
bool Dataset::HasSweeps() const {
  for (const auto& r : rows)
    if (r.sweep != 0) return true;
  return false;
}
bool Dataset::HasSessions() const {
  for (const auto& r : rows)
    if (r.session != 0) return true;
  return false;
}
bool Dataset::HasMarkers() const {
  for (const auto& r : rows)
    if (!r.marker.empty()) return true;
  return false;
}
bool Dataset::HasSplit() const {
  for (const auto& r : rows)
    if (r.split != Split::kNone) return true;
  return false;
}

bool Dataset::HasFromColumns() const {
  for (const auto& r : rows)
    if (r.from_q) return true;
  return false;
}

bool Dataset::HasKind(MeasurementKind kind) const {
  for (const auto& r : rows)
    if (r.kind == kind) return true;
  return false;
}

bool Dataset::AllFullPoints() const {
  for (const auto& r : rows)
    if (!r.IsFullPoint()) return false;
  return true;
}

std::vector<std::string> Dataset::FixtureNames(MeasurementKind kind) const {
  std::vector<std::string> names;
  for (const auto& r : rows) {
    if (r.kind == kind && std::find(names.begin(), names.end(), r.fixture) == names.end()) names.push_back(r.fixture);
  }
  return names;
}

void Dataset::RequireFullPoints(const std::string& who) const {
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].IsFullPoint()) continue;
    ThrowInputError(source, rows[i].line, 0,
                    who + " needs point rows with x, y and z; row " + std::to_string(i + 1) + " is " +
                        rows[i].Description());
  }
}

std::vector<Dataset::Previous> Dataset::PreviousPoses() const {
  std::vector<Previous> out(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].from_q) {
      out[r] = {static_cast<int>(r), true};
    } else if (r > 0) {
      const bool same_pose = rows[r].q.size() == rows[r - 1].q.size() && rows[r].q == rows[r - 1].q;
      out[r] = same_pose ? out[r - 1] : Previous{static_cast<int>(r - 1), false};
    }
  }
  return out;
}

const Eigen::VectorXd* Dataset::PreviousQ(const Previous& previous) const {
  if (previous.row < 0) return nullptr;
  const Measurement& m = rows[static_cast<size_t>(previous.row)];
  return previous.from_columns ? &*m.from_q : &m.q;
}

const std::vector<int64_t>* Dataset::PreviousEncoders(const Previous& previous) const {
  if (previous.row < 0 || previous.from_columns) return nullptr;
  const auto& e = rows[static_cast<size_t>(previous.row)].encoders;
  return e.empty() ? nullptr : &e;
}

Dataset Dataset::SelectRows(const std::vector<int>& indices) const {
  const std::vector<Previous> previous = PreviousPoses();
  Dataset out = *this;
  out.rows.clear();
  out.rows.reserve(indices.size());
  for (int i : indices) {
    Measurement m = rows.at(static_cast<size_t>(i));
    if (const Eigen::VectorXd* q = PreviousQ(previous[static_cast<size_t>(i)])) m.from_q = *q;
    out.rows.push_back(std::move(m));
  }
  return out;
}

Dataset Dataset::Subset(Split which) const {
  if (which == Split::kNone) return *this;
  std::vector<int> indices;
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].split == which) indices.push_back(static_cast<int>(i));
  return SelectRows(indices);
}

namespace {

// What a row of its kind must hold (rows made in code; the reader refuses these with a column).
void ValidateKind(const Measurement& m, const std::string& source, int line, const std::string& row) {
  const bool point = m.kind == MeasurementKind::kPoint;
  if (point && !m.fixture.empty()) ThrowInputError(source, line, 0, row + "a point row names no fixture");
  if (!point && m.fixture.empty()) {
    ThrowInputError(source, line, 0, row + MeasurementKindName(m.kind) + " row without a fixture name");
  }
  if (point && !(m.axes[0] || m.axes[1] || m.axes[2])) {
    ThrowInputError(source, line, 0, row + "a point row measures no axis");
  }
  if (m.orientation && !m.IsFullPoint()) {
    ThrowInputError(source, line, 0, row + "an orientation needs a point with x, y and z");
  }
  if (m.kind == MeasurementKind::kDistance && !(std::isfinite(m.distance) && m.distance >= 0.0)) {
    ThrowInputError(source, line, 0, row + "expected a finite distance >= 0");
  }
}

}  // namespace

void Dataset::Validate(int expected_dof) const {
  if (dof != expected_dof) {
    ThrowInputError(source, header_line, header_line > 0 ? 1 : 0,
                    "the dataset has " + std::to_string(dof) + " joint columns but the robot has " +
                        std::to_string(expected_dof) + " joints");
  }
  for (size_t i = 0; i < rows.size(); ++i) {
    const Measurement& m = rows[i];
    const int line = m.line;
    const std::string row = line > 0 ? "" : "row " + std::to_string(i + 1) + ": ";
    if (m.q.size() != expected_dof) ThrowInputError(source, line, 0, row + "wrong number of joint values");
    if (!m.q.allFinite() || !m.p.allFinite()) ThrowInputError(source, line, 0, row + "non-finite value");
    if (m.from_q && (m.from_q->size() != expected_dof || !m.from_q->allFinite())) {
      ThrowInputError(source, line, 0, row + "expected " + std::to_string(expected_dof) + " finite from_q values");
    }
    if (!m.encoders.empty() && static_cast<int>(m.encoders.size()) != expected_dof) {
      ThrowInputError(source, line, 0, row + "wrong number of encoder values");
    }
    ValidateKind(m, source, line, row);
    if (m.sweep < 0 || m.sweep > expected_dof) {
      ThrowInputError(
          source, line, 0,
          row + "sweep index " + std::to_string(m.sweep) + " out of range 0.." + std::to_string(expected_dof));
    }
  }
}


}  // namespace kincal
