// kincal.Dataset: measurements, one row each, SI units (the file's units are kept only to write it back).
// To and from numpy column by column: q (N x n, rad), p (N x 3, m; NaN where not measured) and the optional
// columns, with kind, fixture and distance (m) when rows measure other than full points.
#include <cmath>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "framework/dataset.h"
#include "python/bindings.h"
#include "python/conversions.h"

namespace kincal::python {
namespace {

const char* SplitName(Split s) { return s == Split::kTrain ? "train" : s == Split::kTest ? "test" : ""; }

Split SplitFrom(const std::string& text, const std::string& what) {
  if (text == "train") return Split::kTrain;
  if (text == "test") return Split::kTest;
  if (text.empty() || text == "all" || text == "none") return Split::kNone;
  throw std::invalid_argument(what + ": expected 'train', 'test' or '' (got '" + text + "')");
}

// The whole table as arrays: the columns the dataset has (DESIGN.md "File contracts"), SI units.
py::dict ToNumpy(const Dataset& d) {
  const long n = static_cast<long>(d.rows.size());
  Eigen::MatrixXd q(n, d.dof), p(n, 3);
  for (long i = 0; i < n; ++i) {
    const Measurement& m = d.rows[i];
    q.row(i) = m.q.transpose();
    for (int a = 0; a < 3; ++a) p(i, a) = m.kind == MeasurementKind::kPoint && m.axes[a] ? m.p[a] : NAN;
  }
  py::dict out;
  out["q"] = q;
  out["p"] = p;
  if (!d.AllFullPoints()) {  // other instruments: each row's kind, the fixture it names, its distance
    py::list kinds, fixtures;
    Eigen::VectorXd distance(n);
    for (long i = 0; i < n; ++i) {
      const Measurement& m = d.rows[i];
      kinds.append(MeasurementKindName(m.kind));
      fixtures.append(m.fixture);
      distance[i] = m.kind == MeasurementKind::kDistance ? m.distance : NAN;
    }
    out["kind"] = kinds;
    out["fixture"] = fixtures;
    out["distance"] = distance;
  }
  if (d.HasOrientation()) {
    Eigen::MatrixXd o(n, 4);
    for (long i = 0; i < n; ++i) {
      const auto& w = d.rows[i].orientation;
      o.row(i) = w ? Eigen::RowVector4d(w->w(), w->x(), w->y(), w->z()) : Eigen::RowVector4d::Constant(NAN);
    }
    out["orientation"] = o;
  }
  if (d.HasEncoders()) {
    py::array_t<int64_t> e({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(d.dof)});
    auto a = e.mutable_unchecked<2>();
    for (long i = 0; i < n; ++i)
      for (int j = 0; j < d.dof; ++j)
        a(i, j) = j < static_cast<int>(d.rows[i].encoders.size()) ? d.rows[i].encoders[j] : 0;
    out["encoders"] = e;
  }
  const auto column = [&](auto get) {
    py::list list;
    for (const auto& m : d.rows) list.append(get(m));
    return list;
  };
  const auto ints = [&](int Measurement::*member) {
    py::array_t<int> a(static_cast<py::ssize_t>(n));
    for (long i = 0; i < n; ++i) a.mutable_at(i) = d.rows[i].*member;
    return a;
  };
  if (d.HasSweeps()) out["sweep"] = ints(&Measurement::sweep);
  if (d.HasMarkers()) out["marker"] = column([](const Measurement& m) { return m.marker; });
  if (d.HasSessions()) out["session"] = ints(&Measurement::session);
  if (d.HasSplit()) out["split"] = column([](const Measurement& m) { return std::string(SplitName(m.split)); });
  if (d.HasFromColumns()) {
    Eigen::MatrixXd f(n, d.dof);
    for (long i = 0; i < n; ++i)
      f.row(i) = d.rows[i].from_q ? Eigen::RowVectorXd(d.rows[i].from_q->transpose())
                                  : Eigen::RowVectorXd::Constant(d.dof, NAN);
    out["from_q"] = f;
  }
  return out;
}

template <typename T>
std::vector<T> Column(const py::object& values, long rows, const char* what) {
  if (values.is_none()) return {};
  std::vector<T> out = values.cast<std::vector<T>>();
  CheckSize(std::string(what) + " (rows)", rows, static_cast<long>(out.size()));
  return out;
}

MeasurementKind KindFrom(const std::string& text) {
  for (MeasurementKind k :
       {MeasurementKind::kPoint, MeasurementKind::kDistance, MeasurementKind::kPlane, MeasurementKind::kFixedPoint}) {
    if (MeasurementKindName(k) == text) return k;
  }
  throw std::invalid_argument("kind: expected 'point', 'distance', 'plane' or 'fixed_point' (got '" + text + "')");
}

// The rows' kinds, fixtures and distances (to_numpy's columns); a point's NaN components are not measured.
void SetKinds(const py::object& kind, const py::object& fixture, const py::object& distance, Dataset* d) {
  const long n = static_cast<long>(d->rows.size());
  const auto kinds = Column<std::string>(kind, n, "kind");
  const auto fixtures = Column<std::string>(fixture, n, "fixture");
  const auto distances = Column<double>(distance, n, "distance");
  for (long i = 0; i < n; ++i) {
    Measurement& m = d->rows[i];
    if (!kinds.empty()) m.kind = KindFrom(kinds[i]);
    if (!fixtures.empty()) m.fixture = fixtures[i];
    if (!distances.empty() && m.kind == MeasurementKind::kDistance) m.distance = distances[i];
    for (int a = 0; a < 3; ++a) {
      m.axes[a] = m.kind == MeasurementKind::kPoint && std::isfinite(m.p[a]);
      if (!m.axes[a]) m.p[a] = 0.0;
    }
  }
}

Dataset FromNumpy(const Eigen::MatrixXd& q, const Eigen::MatrixXd& p, const py::object& orientation,
                  const py::object& encoders, const py::object& sweep, const py::object& marker,
                  const py::object& session, const py::object& split, const py::object& from_q,
                  const py::object& kind, const py::object& fixture, const py::object& distance,
                  const std::string& length_unit, const std::string& angle_unit) {
  const long n = q.rows();
  CheckSize("p (rows)", n, p.rows());
  CheckSize("p (columns)", 3, p.cols());
  Dataset d;
  d.dof = static_cast<int>(q.cols());
  d.length_unit = LengthUnit(length_unit);
  d.angle_unit = AngleUnit(angle_unit);
  d.rows.resize(n);
  for (long i = 0; i < n; ++i) {
    d.rows[i].q = q.row(i).transpose();
    d.rows[i].p = p.row(i).transpose();
  }
  if (!orientation.is_none()) {
    const auto o = orientation.cast<Eigen::MatrixXd>();
    CheckSize("orientation (rows)", n, o.rows());
    CheckSize("orientation (columns qw, qx, qy, qz)", 4, o.cols());
    for (long i = 0; i < n; ++i) d.rows[i].orientation = Eigen::Quaterniond(o(i, 0), o(i, 1), o(i, 2), o(i, 3));
  }
  if (!encoders.is_none()) {
    const auto e = encoders.cast<Eigen::Matrix<int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>();
    CheckSize("encoders (rows)", n, e.rows());
    CheckSize("encoders (columns)", d.dof, e.cols());
    for (long i = 0; i < n; ++i) d.rows[i].encoders.assign(e.row(i).data(), e.row(i).data() + e.cols());
  }
  const auto sweeps = Column<int>(sweep, n, "sweep");
  const auto markers = Column<std::string>(marker, n, "marker");
  const auto sessions = Column<int>(session, n, "session");
  const auto splits = Column<std::string>(split, n, "split");
  for (size_t i = 0; i < sweeps.size(); ++i) d.rows[i].sweep = sweeps[i];
  for (size_t i = 0; i < markers.size(); ++i) d.rows[i].marker = markers[i];
  for (size_t i = 0; i < sessions.size(); ++i) d.rows[i].session = sessions[i];
  for (size_t i = 0; i < splits.size(); ++i) d.rows[i].split = SplitFrom(splits[i], "split");
  if (!from_q.is_none()) {
    const auto f = from_q.cast<Eigen::MatrixXd>();
    CheckSize("from_q (rows)", n, f.rows());
    CheckSize("from_q (columns)", d.dof, f.cols());
    for (long i = 0; i < n; ++i)
      if (f.row(i).allFinite()) d.rows[i].from_q = Eigen::VectorXd(f.row(i).transpose());
  }
  SetKinds(kind, fixture, distance, &d);
  d.Validate(d.dof);
  return d;
}

}  // namespace

void BindDataset(py::module_& m) {
  py::class_<Dataset> dataset(m, "Dataset", R"(Measurements of a robot, one row each, in SI units: commanded joint
angles q (rad) and the measured marker position p (m) in the measurement frame, with optional orientation
(qw, qx, qy, qz), encoder counts, sweep, marker, session, split and from_q columns.)");
  dataset
      .def(py::init(&FromNumpy), py::arg("q"), py::arg("p"), py::kw_only(), py::arg("orientation") = py::none(),
           py::arg("encoders") = py::none(), py::arg("sweep") = py::none(), py::arg("marker") = py::none(),
           py::arg("session") = py::none(), py::arg("split") = py::none(), py::arg("from_q") = py::none(),
           py::arg("kind") = py::none(), py::arg("fixture") = py::none(), py::arg("distance") = py::none(),
           py::arg("length_unit") = "mm", py::arg("angle_unit") = "deg",
           "A dataset from arrays (SI); the units are those save() writes the file in. Other instruments "
           "(docs/instruments.md): kind per row ('point', 'distance', 'plane', 'fixed_point'), the fixture "
           "it names (pivot, plane or point), distance (m); p's NaN components are not measured.")
      .def("to_numpy", &ToNumpy, "Every column the dataset has, as a dict of arrays (SI units).")
      .def_property_readonly(
          "q", [](const Dataset& d) -> py::object { return ToNumpy(d)["q"]; }, "N x n joint angles, rad.")
      .def_property_readonly(
          "p", [](const Dataset& d) -> py::object { return ToNumpy(d)["p"]; },
          "N x 3 marker positions, m; NaN where a row does not measure the component (docs/instruments.md).")
      .def_property_readonly(
          "kind",
          [](const Dataset& d) {
            std::vector<std::string> out;
            for (const auto& m : d.rows) out.push_back(MeasurementKindName(m.kind));
            return out;
          },
          "Each row's kind: 'point' (full or partial), 'distance', 'plane' or 'fixed_point'.")
      .def_property_readonly(
          "fixture",
          [](const Dataset& d) {
            std::vector<std::string> out;
            for (const auto& m : d.rows) out.push_back(m.fixture);
            return out;
          },
          "The pivot, plane or point each row names ('' for a point).")
      .def_property_readonly(
          "distance",
          [](const Dataset& d) {
            Eigen::VectorXd out(d.rows.size());
            for (size_t i = 0; i < d.rows.size(); ++i)
              out[i] = d.rows[i].kind == MeasurementKind::kDistance ? d.rows[i].distance : NAN;
            return out;
          },
          "Each distance row's distance to its pivot, m (NaN on other rows).")
      .def_readonly("dof", &Dataset::dof)
      .def_readwrite("comments", &Dataset::comments)
      .def_readonly("source", &Dataset::source)
      .def_property_readonly("length_unit", [](const Dataset& d) { return d.length_unit.name; })
      .def_property_readonly("angle_unit", [](const Dataset& d) { return d.angle_unit.name; })
      .def("__len__", [](const Dataset& d) { return d.rows.size(); })
      .def(
          "subset", [](const Dataset& d, const std::string& which) { return d.Subset(SplitFrom(which, "subset")); },
          py::arg("which"), "The 'train' or 'test' rows (each keeps the pose that led to it).")
      .def(
          "select_rows",
          [](const Dataset& d, const std::vector<int>& rows) {
            for (int r : rows)
              if (r < 0 || r >= static_cast<int>(d.rows.size()))
                throw std::invalid_argument("select_rows: row " + std::to_string(r) + " is out of range (" +
                                            std::to_string(d.rows.size()) + " rows)");
            return d.SelectRows(rows);
          },
          py::arg("rows"), "Rows by index, in the order given (each keeps the pose that led to it).")
      .def("to_csv", &DatasetToCsv, "The dataset file's text (its units).")
      .def(
          "save", [](const Dataset& d, const py::object& path) { WriteDataset(d, FsPath(path)); }, py::arg("path"),
          "Writes the CSV atomically.")
      .def("__repr__", [](const Dataset& d) {
        return "<kincal.Dataset " + std::to_string(d.rows.size()) + " rows, " + std::to_string(d.dof) + " joints>";
      });

  m.def(
      "load_dataset", [](const py::object& path) { return ReadDataset(FsPath(path)); }, py::arg("path"),
      "Reads a dataset (CSV); kincal.Error on bad input.");
  m.def("parse_dataset", &ParseDatasetCsv, py::arg("text"), py::arg("source") = "<string>");
}

}  // namespace kincal::python
