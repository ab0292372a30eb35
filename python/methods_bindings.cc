// kincal's methods from Python: simulate, identify (any registered estimator or a pipeline), predict,
// evaluate, compensate, run a study, list the methods. The same library calls as the command line's
// subcommands (apps/*_command.cc), so the numbers are the same to the last digit.
#include <algorithm>
#include <cmath>

#include <pybind11/eigen.h>
#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "framework/error.h"
#include "framework/method_options.h"
#include "compensators/compensator.h"
#include "compensators/program.h"
#include "estimators/estimator.h"
#include "robot/prediction.h"
#include "robot/simulator.h"
#include "studies/runner.h"
#include "studies/study.h"
#include "models/model_factory.h"
#include "python/bindings.h"
#include "python/conversions.h"

namespace kincal::python {
namespace {

// Options per method, as `kincal identify --options` reads them (framework/method_options.h).
std::vector<YAML::Node> MethodOptionsFromDict(const py::object& options, const std::vector<std::string>& methods) {
  if (options.is_none()) return std::vector<YAML::Node>(methods.size());
  if (!py::isinstance<py::dict>(options)) throw std::invalid_argument("options: expected a dict");
  return kincal::OptionsPerMethod(ToYaml(options), methods, "options", 0);
}

py::dict Stats(const ErrorStats& s) {
  py::dict d;
  d["count"] = s.count;
  d["mean"] = s.mean;
  d["rms"] = s.rms;
  d["max"] = s.max;
  d["median"] = s.median;
  return d;
}

void CheckMarkers(const Robot& robot, const Dataset& data) {
  for (const auto& row : data.rows) {
    try {
      robot.MarkerPosition(row.marker);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(data.source + ":" + std::to_string(row.line) + ": " + e.what());
    }
  }
}

const Robot& ControllerOr(const Robot* controller, const Robot& robot) {
  const Robot& c = controller ? *controller : robot;
  if (c.dof() != robot.dof()) {
    throw std::invalid_argument("the controller robot has " + std::to_string(c.dof()) + " joints, the robot " +
                                std::to_string(robot.dof()));
  }
  return c;
}

Dataset SimulateFrom(const Robot& nominal, const Robot& truth, const std::string& protocol, int poses, int stops,
                     double step, std::optional<Eigen::VectorXd> start, std::vector<int> order, double noise,
                     double noise_range, bool orientation, double orientation_noise, std::vector<std::string> markers,
                     uint64_t seed, const std::string& instrument, const std::string& axes, int fixtures) {
  SimulatorOptions o;
  o.instrument.instrument = instrument;
  o.instrument.axes = axes;
  o.instrument.fixtures = fixtures;
  o.protocol = protocol;
  o.poses = poses;
  o.stops = stops;
  o.step = step;
  if (start) o.start = *start;
  o.sweep_order = std::move(order);
  o.noise_sigma = noise;
  o.noise_range_coefficient = noise_range;
  o.orientation = orientation;
  o.orientation_noise = orientation_noise;
  o.markers = std::move(markers);
  o.seed = seed;
  o.length_unit = nominal.length_unit;
  o.angle_unit = nominal.angle_unit;
  std::string why;
  if (!o.IsValid(&why)) throw std::invalid_argument("simulate: " + OneLine(why));
  return Simulate(nominal, truth, o);
}

py::tuple Identify(const Robot& nominal, const Dataset& data, const std::string& method, const py::object& options) {
  const std::vector<std::string> methods = SplitComma(method);
  for (const auto& name : methods) Estimators().Get(name);  // unknown names fail before any work
  const std::vector<YAML::Node> per_method = MethodOptionsFromDict(options, methods);
  data.Validate(nominal.dof());
  Robot identified;
  std::vector<EstimationReport> reports;
  {
    py::gil_scoped_release release;
    reports = RunPipeline(methods, per_method, nominal, data, &identified);
  }
  py::object report = ToPython(reports.back().ToJson());
  if (reports.size() > 1) {
    py::list stages;
    for (const auto& r : reports) stages.append(ToPython(r.ToJson()));
    report["stages"] = stages;
  }
  report["brief"] = reports.back().BriefReport();
  return py::make_tuple(identified, report);
}

py::dict Compensate(const Robot& nominal, const Robot& identified, const Eigen::MatrixXd& targets,
                    const std::string& method, const py::object& options, std::optional<Eigen::MatrixXd> seeds,
                    std::optional<Eigen::MatrixXd> from_q) {
  // Targets: N x 3 positions, or N x 16 (rows of 4x4 poses, flattened by the Python wrapper below).
  const bool poses = targets.cols() == 16;
  if (!poses && targets.cols() != 3)
    throw std::invalid_argument("targets: expected N x 3 positions or N x 4 x 4 poses");
  const long n = targets.rows(), dof = nominal.dof();
  if (seeds) CheckSize("seeds (rows)", n, seeds->rows()), CheckSize("seeds (columns)", dof, seeds->cols());
  if (from_q) CheckSize("from_q (rows)", n, from_q->rows()), CheckSize("from_q (columns)", dof, from_q->cols());
  if (!targets.allFinite()) throw std::invalid_argument("targets: expected finite values");
  std::unique_ptr<Compensator> compensator = Compensators().Create(method, ToYaml(options));
  std::vector<CompensationResult> results;
  {
    py::gil_scoped_release release;
    compensator->Prepare(nominal, identified);
    std::vector<CompensationTarget> program(n);
    for (long i = 0; i < n; ++i) {
      CompensationTarget& t = program[i];
      if (poses) {
        t.T_meas_tool.matrix() =
            Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(targets.row(i).eval().data());
      } else {
        t.T_meas_tool.translation() = targets.row(i).transpose();
      }
      t.has_orientation = poses;
      if (seeds) t.seed = seeds->row(i).transpose();
      // A program, as `kincal compensate` runs it: each target from the commands of the one before,
      // unless from_q gives the pose the arm comes from.
      if (from_q && from_q->row(i).allFinite()) t.previous_command = from_q->row(i).transpose();
    }
    results = CompensateProgram(*compensator, program);
  }
  Eigen::MatrixXd q_command(n, dof), q_actual(n, dof);
  Eigen::VectorXd position_error(n), orientation_error(n);
  Eigen::VectorXi iterations(n);
  py::array_t<bool> seed_computed(static_cast<py::ssize_t>(n));
  py::list status;
  for (long i = 0; i < n; ++i) {
    const auto& r = results[i];
    q_command.row(i) = r.q_command.transpose();
    q_actual.row(i) = r.q_actual.transpose();
    position_error[i] = r.report.position_error;
    orientation_error[i] = r.report.orientation_error;
    iterations[i] = r.report.iterations;
    seed_computed.mutable_at(i) = r.report.seed_computed;
    status.append(ToString(r.report.status));
  }
  py::dict out;
  out["q_command"] = q_command;
  out["q_actual"] = q_actual;
  if (identified.drives) {
    py::array_t<int64_t> e({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(dof)});
    auto a = e.mutable_unchecked<2>();
    for (long i = 0; i < n; ++i)
      for (long j = 0; j < dof && j < static_cast<long>(results[i].encoders.size()); ++j)
        a(i, j) = results[i].encoders[j];
    out["encoders"] = e;
  }
  out["status"] = status;
  out["iterations"] = iterations;
  out["position_error"] = position_error;
  out["orientation_error"] = orientation_error;
  out["seed_computed"] = seed_computed;
  return out;
}

template <typename R>
py::list Entries(const R& registry) {
  py::list list;
  for (const auto& name : registry.RegisteredNames()) {
    const auto& e = registry.Get(name);
    py::dict d;
    d["name"] = e.name;
    d["description"] = e.description;
    py::list options;
    for (const OptionDoc& o : e.options) {
      py::dict option;
      option["key"] = o.key;
      option["type"] = o.type;
      option["default"] = o.default_value;
      option["doc"] = o.doc;
      options.append(option);
    }
    d["options"] = options;
    list.append(d);
  }
  return list;
}

// `predict`: where `robot` puts each row's marker, N x 3.
Eigen::MatrixXd PredictRows(const Robot& robot, const Dataset& data, const Robot* nominal) {
  const Robot& controller = ControllerOr(nominal, robot);
  data.Validate(robot.dof());
  CheckMarkers(robot, data);
  const std::vector<Eigen::Vector3d> p = PredictMarkers(controller, robot, data);
  Eigen::MatrixXd out(p.size(), 3);
  for (size_t i = 0; i < p.size(); ++i) out.row(i) = p[i].transpose();
  return out;
}

// `evaluate`: the errors of `robot` in predicting every row, with their statistics.
py::dict EvaluateRows(const Robot& robot, const Dataset& data, const Robot* nominal) {
  const Robot& controller = ControllerOr(nominal, robot);
  data.Validate(robot.dof());
  CheckMarkers(robot, data);
  const PredictionErrors e = EvaluatePredictions(controller, robot, data);
  py::dict d;
  d["position"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(e.position.data(), e.position.size()));
  d["orientation"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(e.orientation.data(), e.orientation.size()));
  d["position_stats"] = Stats(e.position_stats);
  d["orientation_stats"] = Stats(e.orientation_stats);
  return d;
}

// `run_study`: a study file run into `out_path`; a summary dict.
py::dict RunStudyFile(const py::object& path, const py::object& out_path, int threads, const std::string& shard) {
  const Study study = ReadStudyFile(FsPath(path));
  const std::string out = FsPath(out_path);
  StudyRunOptions options;
  ParseShard(shard, &options.shard_index, &options.shard_count);
  options.threads = threads;
  StudyRunSummary s;
  {
    py::gil_scoped_release release;
    s = RunStudy(study, out, options);
  }
  py::dict d;
  d["items_total"] = s.items_total;
  d["items_run"] = s.items_run;
  d["threads"] = s.threads;
  d["seconds"] = s.seconds;
  d["report"] = options.shard_count == 1 ? py::object(py::str(out + "/report.md")) : py::object(py::none());
  return d;
}

}  // namespace

void BindMethods(py::module_& m) {
  m.def(
      "methods",
      []() {
        py::dict d;
        d["models"] = ModelConventions();
        d["estimators"] = Entries(Estimators());
        d["compensators"] = Entries(Compensators());
        return d;
      },
      "Every model convention, estimator and compensator (name, description, availability), as `kincal methods`.");

  m.def("simulate", &SimulateFrom, py::arg("nominal"), py::arg("truth"), py::kw_only(), py::arg("protocol") = "sweep",
        py::arg("poses") = 100, py::arg("stops") = 20, py::arg("step") = 2.0 * M_PI / 180.0,
        py::arg("start") = py::none(), py::arg("order") = std::vector<int>(), py::arg("noise") = 0.0,
        py::arg("noise_range") = 0.0, py::arg("orientation") = false, py::arg("orientation_noise") = 0.0,
        py::arg("markers") = std::vector<std::string>(), py::arg("seed") = 1, py::arg("instrument") = "point",
        py::arg("axes") = "z", py::arg("fixtures") = 3,
        R"(A dataset the instrument would measure on `truth` commanded by `nominal` (robot/simulator.h).
SI: step and orientation_noise in rad, noise in m per axis, noise_range in m per m of distance. Same seed, same data.
instrument: 'point', 'partial' (the `axes` of "xyz"), 'distance', 'plane' or 'socket', against the truth's
fixtures or `fixtures` random ones (robot/simulator_instruments.h, docs/instruments.md).)");

  m.def("identify", &Identify, py::arg("nominal"), py::arg("data"), py::arg("method"), py::arg("options") = py::none(),
        R"(Identifies a robot from `data` (every row; use data.subset('train') for a split file) starting from
`nominal`. `method`: a registered estimator or a comma-separated pipeline; `options`: that estimator's options
as a dict (for a pipeline, keyed by method name). Returns (identified robot, report dict): the last stage's
report as `kincal identify --report` writes it (m, rad), with 'stages' for a pipeline and 'brief'.)");

  m.def("predict", &PredictRows, py::arg("robot"), py::arg("data"), py::arg("nominal") = nullptr,
        R"(Where `robot` puts each row's marker (N x 3, m), as `kincal predict`. `nominal`: the controller whose
ratios turned commanded angles into motor counts (default: the robot itself).)");

  m.def("evaluate", &EvaluateRows, py::arg("robot"), py::arg("data"), py::arg("nominal") = nullptr,
        "Errors of `robot` in predicting every row (m, rad) and their statistics (count, mean, rms, max, median).");

  m.def("_compensate", &Compensate, py::arg("nominal"), py::arg("identified"), py::arg("targets"), py::arg("method"),
        py::arg("options"), py::arg("seeds"), py::arg("from_q"));

  m.def("run_study", &RunStudyFile, py::arg("study"), py::arg("out"), py::kw_only(), py::arg("threads") = 0,
        py::arg("shard") = "1/1",
        "Runs a study file (as `kincal study`): results, plots and report.md in `out`. Returns a summary dict.");

  // compensate: targets as N x 3 positions or N x 4 x 4 poses; numpy reshapes them for the C++ side.
  py::exec(R"(
def compensate(nominal, identified, targets, method, options=None, seeds=None, from_q=None):
    """Joints that make `identified` reach each target, for a controller that believes `nominal` (as
    `kincal compensate`). targets: N x 3 positions (m) or N x 4 x 4 poses T_meas_tool; seeds: the
    controller's N x n joint solutions (default: its inverse kinematics); from_q: N x n commands the arm
    comes from (default: the previous target's). Targets are a program: each is reached from the one before.
    Returns a dict of arrays: q_command (what to command), q_actual, encoders (with drives), status,
    iterations, position_error (m), orientation_error (rad), seed_computed."""
    import numpy as _np
    t = _np.asarray(targets, dtype=float)
    if t.ndim == 3:
        t = t.reshape(t.shape[0], 16)
    elif t.ndim == 1:
        t = t.reshape(1, -1)
    return _compensate(nominal, identified, t, method, options, seeds, from_q)
)",
           m.attr("__dict__"));
}

}  // namespace kincal::python
