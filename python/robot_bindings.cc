// kincal.Robot: a robot file's contents, SI units throughout (metres, radians; the file's units are kept
// only to write it back). The kinematics are the model's: T_meas_tool(q) = T_meas_base T_base_n(q) T_n_tool
// at actual joint angles (framework/kinematic_model.h).
#include <cmath>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "robot/joint_readings.h"
#include "robot/robot_file.h"
#include "python/bindings.h"
#include "python/conversions.h"

namespace kincal::python {
namespace {

// Joint values must fit the robot and be finite, else the model's Eigen code would read out of bounds.
Eigen::VectorXd CheckedJoints(const Robot& robot, const Eigen::VectorXd& q, const char* what = "q") {
  CheckSize(std::string(what) + " (joint angles of " + robot.name + ")", robot.dof(), q.size());
  if (!q.allFinite()) throw std::invalid_argument(std::string(what) + ": expected finite joint values");
  return q;
}

Eigen::Matrix4d Matrix(const Eigen::Isometry3d& T) { return T.matrix(); }

Eigen::Isometry3d Isometry(const Eigen::Matrix4d& M, const char* what) {
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const bool rigid = M.allFinite() && M.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 0.0) &&
                     (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9 && R.determinant() > 0;
  if (!rigid) throw std::invalid_argument(std::string(what) + ": expected a 4x4 rigid transform");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = M;
  return T;
}

// Kinematics: forward kinematics, frames, Jacobians, joint readings.
void BindKinematics(py::class_<Robot>& robot) {
  robot
      .def(
          "fk",
          [](const Robot& r, const Eigen::VectorXd& q) {
            return Matrix(r.model().ForwardKinematics(CheckedJoints(r, q)));
          },
          py::arg("q"), "T_meas_tool (4x4, metres) at actual joint angles q (radians; metres for prismatic joints).")
      .def(
          "frame_poses",
          [](const Robot& r, const Eigen::VectorXd& q) {
            const auto poses = r.model().FramePoses(CheckedJoints(r, q));
            py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
            auto a = out.mutable_unchecked<3>();
            for (size_t k = 0; k < poses.size(); ++k)
              for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) a(k, i, j) = poses[k].matrix()(i, j);
            return out;
          },
          py::arg("q"), "T_meas_frame_i for i = 0..n (0: the base), then T_meas_tool: an (n+2, 4, 4) array.")
      .def(
          "joint_jacobian",
          [](const Robot& r, const Eigen::VectorXd& q, const Eigen::Vector3d& point) {
            return Eigen::MatrixXd(r.model().JointJacobian(CheckedJoints(r, q), point));
          },
          py::arg("q"), py::arg("point") = Eigen::Vector3d::Zero(),
          "6 x n geometric Jacobian: rows 0-2 d(position of `point`, tool frame, m)/dq, rows 3-5 the angular velocity.")
      .def(
          "parameter_jacobian",
          [](const Robot& r, const Eigen::VectorXd& q, const Eigen::Vector3d& point) {
            Matrix6Xd J;
            r.model().ParameterJacobian(CheckedJoints(r, q), point, &J);
            return Eigen::MatrixXd(J);
          },
          py::arg("q"), py::arg("point") = Eigen::Vector3d::Zero(),
          "6 x p Jacobian with respect to every parameter (parameter_names order), same rows as joint_jacobian.")
      .def(
          "actual_angles",
          [](const Robot& r, const Eigen::VectorXd& readings, std::optional<Eigen::VectorXd> previous,
             const Robot* controller) {
            const Robot& c = controller ? *controller : r;
            if (previous) CheckedJoints(r, *previous, "previous");
            return ActualFromReadings(c, r, CheckedJoints(r, readings, "readings"), previous ? &*previous : nullptr);
          },
          py::arg("readings"), py::arg("previous") = py::none(), py::arg("controller") = nullptr,
          "Actual joint angles for the controller's readings (coupling, drive ratios, joint errors of the move from "
          "`previous`), robot/joint_readings.h.");
}

// Name, units and the model's parameters.
void BindParameters(py::class_<Robot>& robot) {
  robot.def_property_readonly("dof", &Robot::dof)
      .def_readwrite("name", &Robot::name)
      .def_property_readonly("convention", [](const Robot& r) { return r.model().convention(); })
      .def_property_readonly(
          "length_unit", [](const Robot& r) { return r.length_unit.name; },
          "The unit the robot file is written in (values here are SI).")
      .def_property_readonly("angle_unit", [](const Robot& r) { return r.angle_unit.name; })
      .def_property_readonly("parameter_names", [](const Robot& r) { return r.model().ParameterNames(); })
      .def_property_readonly("parameter_units",
                             [](const Robot& r) {
                               std::vector<std::string> units;
                               for (const auto& p : r.model().parameter_info())
                                 units.push_back(p.kind == ParameterInfo::Kind::kLength ? "m" : "rad");
                               return units;
                             })
      .def_property(
          "parameters", [](const Robot& r) { return Eigen::VectorXd(r.model().Parameters()); },
          [](Robot& r, const Eigen::VectorXd& v) {
            CheckSize("parameters", r.model().num_parameters(), v.size());
            if (!v.allFinite()) throw std::invalid_argument("parameters: expected finite values");
            r.model().SetParameters(v);
          },
          "Parameter values (m, rad) in parameter_names order.")
      .def_property(
          "free_mask",
          [](const Robot& r) {
            const auto& mask = r.model().FreeMask();
            py::array_t<bool> out(static_cast<py::ssize_t>(mask.size()));
            for (size_t i = 0; i < mask.size(); ++i) out.mutable_at(i) = mask[i];
            return out;
          },
          [](Robot& r, const std::vector<bool>& mask) {
            CheckSize("free_mask", r.model().num_parameters(), static_cast<long>(mask.size()));
            r.model().SetFreeMask(mask);
          },
          "True for the parameters estimators may change.")
      .def(
          "parameter", [](const Robot& r, const std::string& name) { return r.model().Parameter(name); },
          py::arg("name"))
      .def(
          "set_parameter", [](Robot& r, const std::string& name, double value) { r.model().SetParameter(name, value); },
          py::arg("name"), py::arg("value"))
      .def(
          "set_free", [](Robot& r, const std::string& name, bool free) { r.model().SetFree(name, free); },
          py::arg("name"), py::arg("free") = true);
}

// Base, tool, limits, markers; files and copies.
void BindFramesAndFiles(py::class_<Robot>& robot) {
  robot
      .def_property(
          "base", [](const Robot& r) { return Matrix(r.model().base()); },
          [](Robot& r, const Eigen::Matrix4d& T) { r.model().SetBase(Isometry(T, "base")); }, "T_meas_base, 4x4, m.")
      .def_property(
          "tool", [](const Robot& r) { return Matrix(r.model().tool()); },
          [](Robot& r, const Eigen::Matrix4d& T) { r.model().SetTool(Isometry(T, "tool")); }, "T_n_tool, 4x4, m.")
      .def_property(
          "limits",
          [](const Robot& r) {
            Eigen::MatrixX2d out(r.dof(), 2);
            for (int i = 0; i < r.dof(); ++i) out.row(i) << r.Limit(i).first, r.Limit(i).second;
            return out;
          },
          [](Robot& r, const Eigen::MatrixX2d& limits) {
            CheckSize("limits (rows)", r.dof(), limits.rows());
            r.limits.clear();
            for (int i = 0; i < r.dof(); ++i) {
              if (!(limits(i, 0) < limits(i, 1)))
                throw std::invalid_argument("limits: expected min < max for every joint");
              r.limits.emplace_back(limits(i, 0), limits(i, 1));
            }
          },
          "Joint limits in effect, n x 2 (rad; m for prismatic joints).")
      .def_property(
          "markers", [](const Robot& r) { return std::map<std::string, Eigen::Vector3d>(r.markers); },
          [](Robot& r, const std::map<std::string, Eigen::Vector3d>& markers) { r.markers = markers; },
          "Marker positions in the tool frame, m, by id (a copy: assign the whole dict to change it).")
      .def("to_yaml", &RobotToYaml, "The robot file's text (the robot's units; every digit kept).")
      .def(
          "save", [](const Robot& r, const py::object& path) { WriteRobotFile(r, FsPath(path)); }, py::arg("path"),
          "Writes the robot file atomically.")
      .def("copy", [](const Robot& r) { return Robot(r); })
      .def("__copy__", [](const Robot& r) { return Robot(r); })
      .def(
          "__deepcopy__", [](const Robot& r, py::dict) { return Robot(r); }, py::arg("memo"))
      .def("__repr__", [](const Robot& r) {
        return "<kincal.Robot '" + r.name + "' " + r.model().convention() + ", " + std::to_string(r.dof()) + " joints>";
      });
}

}  // namespace

void BindRobot(py::module_& m) {
  py::class_<Robot> robot(m, "Robot", R"(A robot: geometry with named, maskable parameters, limits, markers,
drives and joint level, as a robot file describes it. Everything in SI: metres and radians.)");
  BindKinematics(robot);
  BindParameters(robot);
  BindFramesAndFiles(robot);

  m.def(
      "load_robot", [](const py::object& path) { return ReadRobotFile(FsPath(path)); }, py::arg("path"),
      "Reads a robot file (YAML); kincal.Error on bad input.");
  m.def("parse_robot", &ParseRobotYaml, py::arg("text"), py::arg("source") = "<string>",
        "A robot from the text of a robot file; `source` names it in messages.");
}

}  // namespace kincal::python
