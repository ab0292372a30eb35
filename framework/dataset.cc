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

bool Dataset::HasEncoders() const { return !rows.empty() && !rows.front().encoders.empty(); }
bool Dataset::HasOrientation() const { return !rows.empty() && rows.front().orientation.has_value(); }
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
    if (m.sweep < 0 || m.sweep > expected_dof) {
      ThrowInputError(
          source, line, 0,
          row + "sweep index " + std::to_string(m.sweep) + " out of range 0.." + std::to_string(expected_dof));
    }
  }
}

namespace {

struct Columns {
  std::vector<int> q, enc, from;
  std::vector<Unit> q_units, from_units;
  int x = -1, y = -1, z = -1;
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
    if (name == "qw")
      c.qw = static_cast<int>(i);
    else if (name == "qx")
      c.qx = static_cast<int>(i);
    else if (name == "qy")
      c.qy = static_cast<int>(i);
    else if (name == "qz")
      c.qz = static_cast<int>(i);
    else if (name == "sweep")
      c.sweep = static_cast<int>(i);
    else if (name == "marker")
      c.marker = static_cast<int>(i);
    else if (name == "session")
      c.session = static_cast<int>(i);
    else if (name == "split")
      c.split = static_cast<int>(i);
    else if (IsIndexed(name, "enc", &index))
      enc[index] = static_cast<int>(i);
    else if (SplitUnit(name, &stem, &unit) && (IsIndexed(stem, "q", &index) || IsIndexed(stem, "from_q", &index))) {
      Unit u;
      if (unit == "deg" || unit == "rad")
        u = AngleUnit(unit);
      else if (unit == "mm" || unit == "m")
        u = LengthUnit(unit);
      else
        fail(i, "unknown unit '" + unit + "' in column '" + name + "' (expected deg, rad, mm or m)");
      (stem[0] == 'f' ? from : q)[index] = {static_cast<int>(i), u};
    } else if (SplitUnit(name, &stem, &unit) && (stem == "x" || stem == "y" || stem == "z")) {
      Unit u;
      try {
        u = LengthUnit(unit);
      } catch (const std::invalid_argument& e) {
        fail(i, std::string("column '") + name + "': " + e.what());
      }
      if (have_length && u.name != c.length.name) fail(i, "x, y and z must share one length unit");
      c.length = u;
      have_length = true;
      (stem == "x" ? c.x : stem == "y" ? c.y : c.z) = static_cast<int>(i);
    } else {
      fail(i, "unknown column '" + name +
                  "' (expected q1_deg.., x_mm, y_mm, z_mm, enc1.., qw, qx, qy, qz, sweep, marker, session, split, "
                  "from_q1_deg..)");
    }
  }
  int expected = 1;
  for (const auto& [index, col] : q) {
    if (index != expected)
      ThrowInputError(source, t.header.line, 1, "joint column q" + std::to_string(expected) + "_ is missing");
    c.q.push_back(col.first);
    c.q_units.push_back(col.second);
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
      c.from.push_back(from[i].first);
      c.from_units.push_back(from[i].second);
    }
  }
  if (!enc.empty()) {
    if (static_cast<int>(enc.size()) != static_cast<int>(q.size())) {
      ThrowInputError(source, t.header.line, 1,
                      "expected one enc column per joint (enc1..enc" + std::to_string(q.size()) + ")");
    }
    for (int i = 1; i <= static_cast<int>(enc.size()); ++i) {
      if (!enc.count(i)) ThrowInputError(source, t.header.line, 1, "column enc" + std::to_string(i) + " is missing");
      c.enc.push_back(enc[i]);
    }
  }
  if (c.x < 0 || c.y < 0 || c.z < 0) {
    ThrowInputError(source, t.header.line, 1, "expected position columns x_mm, y_mm, z_mm (or x_m, y_m, z_m)");
  }
  const int orientation = (c.qw >= 0) + (c.qx >= 0) + (c.qy >= 0) + (c.qz >= 0);
  if (orientation != 0 && orientation != 4)
    ThrowInputError(source, t.header.line, 1, "expected all of qw, qx, qy, qz or none");
  return c;
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
  for (const CsvRow& row : t.rows) {
    const auto number = [&](int col, const char* what) {
      double v = 0.0;
      if (!ParseDouble(row.cells[col], &v)) {
        ThrowInputError(source, row.line, row.columns[col],
                        std::string("expected a finite number for ") + what + ", got '" + row.cells[col] + "'");
      }
      return v;
    };
    const auto integer = [&](int col, const char* what) {
      const double v = number(col, what);
      if (v != std::floor(v) || std::abs(v) > 9.0e15) {
        ThrowInputError(source, row.line, row.columns[col], std::string("expected an integer for ") + what);
      }
      return static_cast<int64_t>(v);
    };
    Measurement m;
    m.line = row.line;
    m.q.resize(data.dof);
    for (int i = 0; i < data.dof; ++i) m.q[i] = number(c.q[i], "a joint angle") * c.q_units[i].to_si;
    m.p = Eigen::Vector3d(number(c.x, "x"), number(c.y, "y"), number(c.z, "z")) * c.length.to_si;
    for (int col : c.enc) m.encoders.push_back(integer(col, "an encoder count"));
    // A row with every from_q cell empty has no explicit previous pose; a partly filled one is an error.
    int from_cells = 0;
    for (int col : c.from) from_cells += !row.cells[col].empty();
    if (from_cells == data.dof && data.dof > 0) {
      Eigen::VectorXd from(data.dof);
      for (int i = 0; i < data.dof; ++i) from[i] = number(c.from[i], "a from_q joint angle") * c.from_units[i].to_si;
      m.from_q = from;
    } else if (from_cells != 0) {
      ThrowInputError(source, row.line, row.columns[c.from[0]],
                      "expected every from_q cell of the row filled, or none");
    }
    if (c.qw >= 0) {
      Eigen::Quaterniond quat(number(c.qw, "qw"), number(c.qx, "qx"), number(c.qy, "qy"), number(c.qz, "qz"));
      if (std::abs(quat.norm() - 1.0) > 1e-6) {
        ThrowInputError(source, row.line, row.columns[c.qw], "expected a unit quaternion (qw, qx, qy, qz)");
      }
      // Normalise only what is not unit to rounding already, so that writing and reading back keeps the bits.
      m.orientation =
          std::abs(quat.squaredNorm() - 1.0) <= 4 * std::numeric_limits<double>::epsilon() ? quat : quat.normalized();
    }
    const auto small_integer = [&](int col, const char* what) {
      const int64_t v = integer(col, what);
      if (std::abs(v) > 1000000)
        ThrowInputError(source, row.line, row.columns[col],
                        std::string("expected ") + what + " between -1000000 and 1000000");
      return static_cast<int>(v);
    };
    if (c.sweep >= 0 && !row.cells[c.sweep].empty()) m.sweep = small_integer(c.sweep, "sweep");
    if (c.marker >= 0) m.marker = row.cells[c.marker];
    if (c.session >= 0 && !row.cells[c.session].empty()) m.session = small_integer(c.session, "session");
    if (c.split >= 0) {
      const std::string& s = row.cells[c.split];
      if (s == "train")
        m.split = Split::kTrain;
      else if (s == "test")
        m.split = Split::kTest;
      else if (!s.empty())
        ThrowInputError(source, row.line, row.columns[c.split], "expected split 'train' or 'test', got '" + s + "'");
    }
    data.rows.push_back(std::move(m));
  }
  return data;
}

Dataset ReadDataset(const std::string& path) { return ParseDatasetCsv(ReadFileToString(path), path); }

std::string DatasetToCsv(const Dataset& data) {
  std::ostringstream out;
  for (const auto& c : data.comments) out << "# " << c << "\n";
  const bool enc = data.HasEncoders(), ori = data.HasOrientation(), sweep = data.HasSweeps(),
             marker = data.HasMarkers(), session = data.HasSessions(), split = data.HasSplit();
  std::vector<std::string> header;
  for (int i = 1; i <= data.dof; ++i) header.push_back("q" + std::to_string(i) + "_" + data.angle_unit.name);
  for (const char* axis : {"x", "y", "z"}) header.push_back(std::string(axis) + "_" + data.length_unit.name);
  if (enc)
    for (int i = 1; i <= data.dof; ++i) header.push_back("enc" + std::to_string(i));
  if (ori)
    for (const char* k : {"qw", "qx", "qy", "qz"}) header.push_back(k);
  if (sweep) header.push_back("sweep");
  if (marker) header.push_back("marker");
  if (session) header.push_back("session");
  if (split) header.push_back("split");
  const bool from = data.HasFromColumns();
  if (from)
    for (int i = 1; i <= data.dof; ++i) header.push_back("from_q" + std::to_string(i) + "_" + data.angle_unit.name);
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  for (const Measurement& m : data.rows) {
    std::string line;
    const auto add = [&](const std::string& s) { line += (line.empty() ? "" : ",") + s; };
    for (int i = 0; i < data.dof; ++i) add(FormatInUnit(m.q[i], data.angle_unit));
    for (int k = 0; k < 3; ++k) add(FormatInUnit(m.p[k], data.length_unit));
    if (enc)
      for (int64_t e : m.encoders) add(std::to_string(e));
    if (ori) {
      const Eigen::Quaterniond qq = m.orientation.value_or(Eigen::Quaterniond::Identity());
      for (double v : {qq.w(), qq.x(), qq.y(), qq.z()}) add(FormatExact(v));
    }
    if (sweep) add(std::to_string(m.sweep));
    if (marker) add(m.marker);
    if (session) add(std::to_string(m.session));
    if (split) add(m.split == Split::kTrain ? "train" : m.split == Split::kTest ? "test" : "");
    if (from)
      for (int i = 0; i < data.dof; ++i) add(m.from_q ? FormatInUnit((*m.from_q)[i], data.angle_unit) : "");
    out << line << "\n";
  }
  return out.str();
}

void WriteDataset(const Dataset& data, const std::string& path) {
  // Never a NaN written silently: a dataset made from a robot with values out of range is refused.
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    const bool finite = m.q.allFinite() && m.p.allFinite() && (!m.orientation || m.orientation->coeffs().allFinite()) &&
                        (!m.from_q || m.from_q->allFinite());
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
