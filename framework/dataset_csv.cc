// Reading and writing dataset CSV files (framework/dataset.h gives the columns).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "framework/atomic_file.h"
#include "framework/csv.h"
#include "framework/dataset.h"
#include "framework/error.h"
#include "framework/memory.h"

namespace kincal {
namespace {

struct Columns {
  std::vector<int> q, enc, from;
  std::vector<Unit> q_units, from_units;
  int x = -1, y = -1, z = -1, distance = -1;
  int pivot = -1, plane = -1, point = -1;
  Unit length;
  int qw = -1, qx = -1, qy = -1, qz = -1;
  int sweep = -1, marker = -1, session = -1, split = -1;
};

bool SplitUnit(const std::string& name, std::string* stem, std::string* unit) {
  const size_t us = name.rfind('_');
  if (us == std::string::npos) return false;
  *stem = name.substr(0, us);
  *unit = name.substr(us + 1);
  return true;
}

bool IsIndexed(const std::string& stem, const std::string& prefix, int* index) {
  if (stem.size() <= prefix.size() || stem.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string digits = stem.substr(prefix.size());
  if (digits.find_first_not_of("0123456789") != std::string::npos || digits[0] == '0') return false;
  // No robot has a million joints; longer digit strings (q99999999999999999999_deg) would overflow int
  // and are reported as unknown columns by the caller.
  if (digits.size() > 6) return false;
  *index = std::stoi(digits);
  return true;
}

// The column of a name without a unit, or -1.
int* PlainColumn(Columns* c, const std::string& name) {
  static const std::map<std::string, int Columns::*> plain = {
      {"qw", &Columns::qw},         {"qx", &Columns::qx},         {"qy", &Columns::qy},
      {"qz", &Columns::qz},         {"sweep", &Columns::sweep},   {"marker", &Columns::marker},
      {"session", &Columns::session}, {"split", &Columns::split}, {"pivot", &Columns::pivot},
      {"plane", &Columns::plane},   {"point", &Columns::point}};
  const auto it = plain.find(name);
  return it == plain.end() ? nullptr : &(c->*(it->second));
}

// Orders the indexed columns (q, from_q, enc) and checks that none is missing.
void OrderIndexed(const CsvTable& t, const std::string& source, const std::map<int, std::pair<int, Unit>>& q,
                  std::map<int, std::pair<int, Unit>> from, std::map<int, int> enc, Columns* c) {
  int expected = 1;
  for (const auto& [index, col] : q) {
    if (index != expected)
      ThrowInputError(source, t.header.line, 1, "joint column q" + std::to_string(expected) + "_ is missing");
    c->q.push_back(col.first);
    c->q_units.push_back(col.second);
    ++expected;
  }
  if (!from.empty()) {
    if (from.size() != q.size()) {
      ThrowInputError(source, t.header.line, 1,
                      "expected one from_q column per joint (from_q1_..from_q" + std::to_string(q.size()) + "_)");
    }
    for (int i = 1; i <= static_cast<int>(from.size()); ++i) {
      if (!from.count(i))
        ThrowInputError(source, t.header.line, 1, "column from_q" + std::to_string(i) + "_ is missing");
      c->from.push_back(from[i].first);
      c->from_units.push_back(from[i].second);
    }
  }
  if (!enc.empty()) {
    if (static_cast<int>(enc.size()) != static_cast<int>(q.size())) {
      ThrowInputError(source, t.header.line, 1,
                      "expected one enc column per joint (enc1..enc" + std::to_string(q.size()) + ")");
    }
    for (int i = 1; i <= static_cast<int>(enc.size()); ++i) {
      if (!enc.count(i)) ThrowInputError(source, t.header.line, 1, "column enc" + std::to_string(i) + " is missing");
      c->enc.push_back(enc[i]);
    }
  }
}

// The header's measurement columns must make sense together.
void CheckMeasurementColumns(const CsvTable& t, const std::string& source, const Columns& c) {
  const int positions = (c.x >= 0) + (c.y >= 0) + (c.z >= 0);
  const bool others = c.distance >= 0 || c.pivot >= 0 || c.plane >= 0 || c.point >= 0;
  if (positions != 3 && (positions != 0 || !others)) {
    ThrowInputError(source, t.header.line, 1,
                    "expected position columns x_mm, y_mm, z_mm (or x_m, y_m, z_m), or the columns of another "
                    "instrument (distance_mm with pivot, plane, point)");
  }
  if ((c.distance >= 0) != (c.pivot >= 0)) {
    ThrowInputError(source, t.header.line, 1, "expected a distance column (distance_mm or distance_m) and a pivot "
                                              "column together");
  }
  const int orientation = (c.qw >= 0) + (c.qx >= 0) + (c.qy >= 0) + (c.qz >= 0);
  if (orientation != 0 && orientation != 4)
    ThrowInputError(source, t.header.line, 1, "expected all of qw, qx, qy, qz or none");
  if (orientation == 4 && positions != 3)
    ThrowInputError(source, t.header.line, 1, "an orientation (qw, qx, qy, qz) needs the columns x, y and z");
}

Columns MapColumns(const CsvTable& t, const std::string& source) {
  Columns c;
  std::map<int, std::pair<int, Unit>> q, from;
  std::map<int, int> enc;
  const auto fail = [&](size_t i, const std::string& what) {
    ThrowInputError(source, t.header.line, t.header.columns[i], what);
  };
  bool have_length = false;
  for (size_t i = 0; i < t.header.cells.size(); ++i) {
    const std::string& name = t.header.cells[i];
    std::string stem, unit;
    int index = 0;
    if (int* column = PlainColumn(&c, name)) {
      *column = static_cast<int>(i);
    } else if (IsIndexed(name, "enc", &index)) {
      enc[index] = static_cast<int>(i);
    } else if (SplitUnit(name, &stem, &unit) && (IsIndexed(stem, "q", &index) || IsIndexed(stem, "from_q", &index))) {
      Unit u;
      if (unit == "deg" || unit == "rad")
        u = AngleUnit(unit);
      else if (unit == "mm" || unit == "m")
        u = LengthUnit(unit);
      else
        fail(i, "unknown unit '" + unit + "' in column '" + name + "' (expected deg, rad, mm or m)");
      (stem[0] == 'f' ? from : q)[index] = {static_cast<int>(i), u};
    } else if (SplitUnit(name, &stem, &unit) && (stem == "x" || stem == "y" || stem == "z" || stem == "distance")) {
      Unit u;
      try {
        u = LengthUnit(unit);
      } catch (const std::invalid_argument& e) {
        fail(i, std::string("column '") + name + "': " + e.what());
      }
      if (have_length && u.name != c.length.name) {
        fail(i, stem == "distance" ? "column '" + name + "' must be in the unit of x, y and z"
                                   : std::string("x, y and z must share one length unit (and distance)"));
      }
      c.length = u;
      have_length = true;
      (stem == "x" ? c.x : stem == "y" ? c.y : stem == "z" ? c.z : c.distance) = static_cast<int>(i);
    } else {
      fail(i, "unknown column '" + name +
                  "' (expected q1_deg.., x_mm, y_mm, z_mm, distance_mm, pivot, plane, point, enc1.., qw, qx, qy, "
                  "qz, sweep, marker, session, split, from_q1_deg..)");
    }
  }
  OrderIndexed(t, source, q, from, enc, &c);
  CheckMeasurementColumns(t, source, c);
  return c;
}

// Reads one row's cells.
class RowReader {
 public:
  RowReader(const CsvRow& row, const std::string& source) : row_(row), source_(source) {}

  bool Has(int col) const { return col >= 0 && !row_.cells[col].empty(); }
  const std::string& Cell(int col) const { return row_.cells[col]; }
  [[noreturn]] void Fail(int col, const std::string& what) const {
    ThrowInputError(source_, row_.line, col >= 0 ? row_.columns[col] : 1, what);
  }
  double Number(int col, const char* what) const {
    double v = 0.0;
    if (!ParseDouble(row_.cells[col], &v)) {
      Fail(col, std::string("expected a finite number for ") + what + ", got '" + row_.cells[col] + "'");
    }
    return v;
  }
  int64_t Integer(int col, const char* what) const {
    const double v = Number(col, what);
    if (v != std::floor(v) || std::abs(v) > 9.0e15) Fail(col, std::string("expected an integer for ") + what);
    return static_cast<int64_t>(v);
  }
  int SmallInteger(int col, const char* what) const {
    const int64_t v = Integer(col, what);
    if (std::abs(v) > 1000000) Fail(col, std::string("expected ") + what + " between -1000000 and 1000000");
    return static_cast<int>(v);
  }

 private:
  const CsvRow& row_;
  const std::string& source_;
};

// The row's kind from its fixture cells; a row names at most one fixture.
void ReadKind(const RowReader& r, const Columns& c, Measurement* m) {
  const std::pair<int, MeasurementKind> named[3] = {
      {c.pivot, MeasurementKind::kDistance}, {c.plane, MeasurementKind::kPlane}, {c.point, MeasurementKind::kFixedPoint}};
  int first = -1;
  for (const auto& [col, kind] : named) {
    if (!r.Has(col)) continue;
    if (first >= 0) {
      r.Fail(col, "a row names one fixture; this one names '" + r.Cell(first) + "' and '" + r.Cell(col) + "'");
    }
    first = col;
    m->kind = kind;
    m->fixture = r.Cell(col);
  }
  const int positions[3] = {c.x, c.y, c.z};
  const int* given = std::find_if(positions, positions + 3, [&](int col) { return r.Has(col); });
  if (m->kind == MeasurementKind::kPoint && r.Has(c.distance)) r.Fail(c.distance, "a distance row needs a pivot name");
  if (m->kind == MeasurementKind::kPoint && given == positions + 3) {
    r.Fail(-1, "the row measures nothing: expected x, y or z, a distance with a pivot, a plane or a point");
  }
  const std::string what = m->kind == MeasurementKind::kDistance ? "a distance row (pivot '" + m->fixture + "')"
                           : m->kind == MeasurementKind::kPlane  ? "a plane row (plane '" + m->fixture + "')"
                                                                 : "a fixed-point row (point '" + m->fixture + "')";
  if (m->kind != MeasurementKind::kPoint && given != positions + 3) {
    r.Fail(*given, what + " has no coordinates; expected x, y and z empty");
  }
  if (m->kind != MeasurementKind::kPoint && r.Has(c.qw)) r.Fail(c.qw, what + " has no orientation");
  if (m->kind == MeasurementKind::kDistance) {
    if (!r.Has(c.distance)) r.Fail(c.pivot, what + " needs a distance (distance_" + c.length.name + ")");
    m->distance = r.Number(c.distance, "a distance") * c.length.to_si;
    if (m->distance < 0.0) r.Fail(c.distance, "expected a distance >= 0, got " + r.Cell(c.distance));
  } else if (r.Has(c.distance)) {
    r.Fail(c.distance, what + " has no distance");
  }
}

void ReadPoint(const RowReader& r, const Columns& c, Measurement* m) {
  const int positions[3] = {c.x, c.y, c.z};
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    m->axes[k] = r.Has(positions[k]);
    if (m->axes[k]) m->p[k] = r.Number(positions[k], names[k]) * c.length.to_si;
  }
  if (c.qw < 0) return;
  const int given = r.Has(c.qw) + r.Has(c.qx) + r.Has(c.qy) + r.Has(c.qz);
  if (given == 0) return;
  if (given != 4) r.Fail(c.qw, "expected every cell of qw, qx, qy, qz filled, or none");
  if (!m->IsFullPoint()) r.Fail(c.qw, "an orientation needs x, y and z");
  Eigen::Quaterniond quat(r.Number(c.qw, "qw"), r.Number(c.qx, "qx"), r.Number(c.qy, "qy"), r.Number(c.qz, "qz"));
  if (std::abs(quat.norm() - 1.0) > 1e-6) r.Fail(c.qw, "expected a unit quaternion (qw, qx, qy, qz)");
  // Normalise only what is not unit to rounding already, so that writing and reading back keeps the bits.
  m->orientation =
      std::abs(quat.squaredNorm() - 1.0) <= 4 * std::numeric_limits<double>::epsilon() ? quat : quat.normalized();
}

Measurement ReadRow(const CsvRow& row, const std::string& source, const Columns& c, int dof) {
  const RowReader r(row, source);
  Measurement m;
  m.line = row.line;
  m.q.resize(dof);
  for (int i = 0; i < dof; ++i) m.q[i] = r.Number(c.q[i], "a joint angle") * c.q_units[i].to_si;
  ReadKind(r, c, &m);
  if (m.kind == MeasurementKind::kPoint) ReadPoint(r, c, &m);
  for (int col : c.enc) m.encoders.push_back(r.Integer(col, "an encoder count"));
  // A row with every from_q cell empty has no explicit previous pose; a partly filled one is an error.
  int from_cells = 0;
  for (int col : c.from) from_cells += r.Has(col);
  if (from_cells == dof && dof > 0) {
    Eigen::VectorXd from(dof);
    for (int i = 0; i < dof; ++i) from[i] = r.Number(c.from[i], "a from_q joint angle") * c.from_units[i].to_si;
    m.from_q = from;
  } else if (from_cells != 0) {
    r.Fail(c.from[0], "expected every from_q cell of the row filled, or none");
  }
  if (r.Has(c.sweep)) m.sweep = r.SmallInteger(c.sweep, "sweep");
  if (c.marker >= 0) m.marker = r.Cell(c.marker);
  if (r.Has(c.session)) m.session = r.SmallInteger(c.session, "session");
  if (c.split >= 0) {
    const std::string& s = r.Cell(c.split);
    if (s == "train")
      m.split = Split::kTrain;
    else if (s == "test")
      m.split = Split::kTest;
    else if (!s.empty())
      r.Fail(c.split, "expected split 'train' or 'test', got '" + s + "'");
  }
  return m;
}

}  // namespace

Dataset ParseDatasetCsv(const std::string& text, const std::string& source) {
  {
    // The cells as strings (CsvTable) and the rows (Measurement) are held at once: about this much.
    const double lines = static_cast<double>(std::count(text.begin(), text.end(), '\n')) +
                         (text.empty() || text.back() != '\n' ? 1.0 : 0.0);
    const double cells = static_cast<double>(std::count(text.begin(), text.end(), ',')) + lines;
    const double bytes = cells * (sizeof(std::string) + sizeof(int) + 8.0) +
                         lines * (sizeof(CsvRow) + sizeof(Measurement) + 64.0) + static_cast<double>(text.size());
    CheckMemory(source, 0, bytes, "reading " + std::to_string(static_cast<long long>(lines)) + " lines");
  }
  const CsvTable t = ParseCsv(text, source);
  const Columns c = MapColumns(t, source);
  Dataset data;
  data.source = source;
  data.header_line = t.header.line;
  data.comments = t.comments;
  data.dof = static_cast<int>(c.q.size());
  data.length_unit = c.length;
  if (!c.q_units.empty()) data.angle_unit = c.q_units.front();
  data.rows.reserve(t.rows.size());
  for (const CsvRow& row : t.rows) data.rows.push_back(ReadRow(row, source, c, data.dof));
  return data;
}

Dataset ReadDataset(const std::string& path) { return ParseDatasetCsv(ReadFileToString(path), path); }

namespace {

// A file without rows still names the columns of one instrument, so that it reads back: the tracker's
// where the file gave a length unit, else the socket's (a name needs no unit).
bool WritesPointColumns(const Dataset& data) {
  return data.HasKind(MeasurementKind::kPoint) || (data.rows.empty() && !data.length_unit.name.empty());
}
bool WritesFixedPointColumn(const Dataset& data) {
  return data.HasKind(MeasurementKind::kFixedPoint) || (data.rows.empty() && data.length_unit.name.empty());
}

std::vector<std::string> Header(const Dataset& data) {
  std::vector<std::string> header;
  for (int i = 1; i <= data.dof; ++i) header.push_back("q" + std::to_string(i) + "_" + data.angle_unit.name);
  if (WritesPointColumns(data))
    for (const char* axis : {"x", "y", "z"}) header.push_back(std::string(axis) + "_" + data.length_unit.name);
  if (data.HasKind(MeasurementKind::kDistance)) {
    header.push_back("distance_" + data.length_unit.name);
    header.push_back("pivot");
  }
  if (data.HasKind(MeasurementKind::kPlane)) header.push_back("plane");
  if (WritesFixedPointColumn(data)) header.push_back("point");
  if (data.HasEncoders())
    for (int i = 1; i <= data.dof; ++i) header.push_back("enc" + std::to_string(i));
  if (data.HasOrientation())
    for (const char* k : {"qw", "qx", "qy", "qz"}) header.push_back(k);
  if (data.HasSweeps()) header.push_back("sweep");
  if (data.HasMarkers()) header.push_back("marker");
  if (data.HasSessions()) header.push_back("session");
  if (data.HasSplit()) header.push_back("split");
  if (data.HasFromColumns())
    for (int i = 1; i <= data.dof; ++i) header.push_back("from_q" + std::to_string(i) + "_" + data.angle_unit.name);
  return header;
}

// The row's measurement cells: x, y, z, distance, pivot, plane, point as the header has them.
void AddMeasurementCells(const Dataset& data, const Measurement& m, std::vector<std::string>* cells) {
  const bool point = m.kind == MeasurementKind::kPoint;
  if (WritesPointColumns(data)) {
    for (int k = 0; k < 3; ++k) cells->push_back(point && m.axes[k] ? FormatInUnit(m.p[k], data.length_unit) : "");
  }
  const auto named = [&](MeasurementKind kind) { return m.kind == kind ? m.fixture : std::string(); };
  if (data.HasKind(MeasurementKind::kDistance)) {
    const bool distance = m.kind == MeasurementKind::kDistance;
    cells->push_back(distance ? FormatInUnit(m.distance, data.length_unit) : "");
    cells->push_back(named(MeasurementKind::kDistance));
  }
  if (data.HasKind(MeasurementKind::kPlane)) cells->push_back(named(MeasurementKind::kPlane));
  if (WritesFixedPointColumn(data)) cells->push_back(named(MeasurementKind::kFixedPoint));
}

}  // namespace

std::string DatasetToCsv(const Dataset& data) {
  std::ostringstream out;
  for (const auto& c : data.comments) out << "# " << c << "\n";
  const std::vector<std::string> header = Header(data);
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  const bool enc = data.HasEncoders(), ori = data.HasOrientation(), sweep = data.HasSweeps(),
             marker = data.HasMarkers(), session = data.HasSessions(), split = data.HasSplit(),
             from = data.HasFromColumns();
  std::vector<std::string> cells;
  for (const Measurement& m : data.rows) {
    cells.clear();
    for (int i = 0; i < data.dof; ++i) cells.push_back(FormatInUnit(m.q[i], data.angle_unit));
    AddMeasurementCells(data, m, &cells);
    if (enc)
      for (size_t i = 0; i < static_cast<size_t>(data.dof); ++i)
        cells.push_back(i < m.encoders.size() ? std::to_string(m.encoders[i]) : "");
    if (ori) {
      for (int k = 0; k < 4; ++k) {
        if (!m.orientation) {
          cells.emplace_back();
          continue;
        }
        const Eigen::Quaterniond& qq = *m.orientation;
        cells.push_back(FormatExact(k == 0 ? qq.w() : k == 1 ? qq.x() : k == 2 ? qq.y() : qq.z()));
      }
    }
    if (sweep) cells.push_back(std::to_string(m.sweep));
    if (marker) cells.push_back(m.marker);
    if (session) cells.push_back(std::to_string(m.session));
    if (split) cells.push_back(m.split == Split::kTrain ? "train" : m.split == Split::kTest ? "test" : "");
    if (from)
      for (int i = 0; i < data.dof; ++i) cells.push_back(m.from_q ? FormatInUnit((*m.from_q)[i], data.angle_unit) : "");
    for (size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
    out << "\n";
  }
  return out.str();
}

void WriteDataset(const Dataset& data, const std::string& path) {
  // Never a NaN written silently: a dataset made from a robot with values out of range is refused.
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    const bool finite = m.q.allFinite() && m.p.allFinite() && std::isfinite(m.distance) &&
                        (!m.orientation || m.orientation->coeffs().allFinite()) && (!m.from_q || m.from_q->allFinite());
    if (!finite) {
      ThrowInputError(path, 0, 0,
                      "row " + std::to_string(i + 1) +
                          " would hold non-finite values (NaN or infinite): "
                          "values out of range in the robot files?");
    }
  }
  WriteFileAtomically(path, DatasetToCsv(data));
}

}  // namespace kincal
