// kincal.Dataset: measurements, one row each, SI units (the file's units are kept only to write it back).
// To and from numpy column by column: q (N x n, rad), p (N x 3, m) and the optional columns.
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
    q.row(i) = d.rows[i].q.transpose();
    p.row(i) = d.rows[i].p.transpose();
  }
  py::dict out;
  out["q"] = q;
  out["p"] = p;
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

Dataset FromNumpy(const Eigen::MatrixXd& q, const Eigen::MatrixXd& p, const py::object& orientation,
                  const py::object& encoders, const py::object& sweep, const py::object& marker,
                  const py::object& session, const py::object& split, const py::object& from_q,
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
           py::arg("length_unit") = "mm", py::arg("angle_unit") = "deg",
           "A dataset from arrays (SI); the units are those save() writes the file in.")
      .def("to_numpy", &ToNumpy, "Every column the dataset has, as a dict of arrays (SI units).")
      .def_property_readonly(
          "q", [](const Dataset& d) -> py::object { return ToNumpy(d)["q"]; }, "N x n joint angles, rad.")
      .def_property_readonly(
          "p", [](const Dataset& d) -> py::object { return ToNumpy(d)["p"]; }, "N x 3 marker positions, m.")
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
