#include "robot/ur_kinematics.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/math.h"
#include "framework/units.h"
#include "models/conversion.h"
#include "models/urdf_model.h"
#include "robot/robot_file_reader.h"

namespace kincal {
namespace {

const char* const kJoints[6] = {"shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"};
const char* const kKeys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string Stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

YAML::Node Load(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    ThrowInputError(source, e.mark.line + 1, e.mark.column + 1, e.msg);
  }
}

// Joint i's frame at q = 0 in the measurement frame: z along its axis (the positive sense of q), origin on
// it, the joint's zero offset turned in, so the chain is M_1 Rz(q_1) M_1^-1 M_2 Rz(q_2) ... of these.
std::vector<Eigen::Isometry3d> JointFramesAtZero(const KinematicModel& model) {
  const std::unique_ptr<KinematicModel> converted = ConvertModel(model, "urdf");
  const auto& urdf = dynamic_cast<const UrdfModel&>(*converted);
  const std::vector<Eigen::Isometry3d> frames = urdf.FramePoses(Eigen::VectorXd::Zero(urdf.dof()));
  std::vector<Eigen::Isometry3d> out;
  for (int i = 0; i < urdf.dof(); ++i) {
    const std::string n = std::to_string(i + 1);
    const Eigen::Matrix3d R_axis =
        (Eigen::AngleAxisd(urdf.Parameter("axis_azimuth_" + n), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(urdf.Parameter("axis_tilt_" + n), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(urdf.Parameter("offset_" + n), Eigen::Vector3d::UnitZ()))
            .toRotationMatrix();
    Eigen::Isometry3d M = frames[i] * urdf.JointOrigin(i);
    M.linear() = M.linear() * R_axis;
    out.push_back(M);
  }
  return out;
}

// x y z (mm) and roll pitch yaw (deg) of a pose, for the messages.
std::string PoseWords(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d p = T.translation() * 1e3, rpy = RpyFromRotation(T.linear()) * (180.0 / M_PI);
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "xyz [%.6g, %.6g, %.6g] mm, rpy [%.6g, %.6g, %.6g] deg", p.x() + 0.0,
                p.y() + 0.0, p.z() + 0.0, rpy.x() + 0.0, rpy.y() + 0.0, rpy.z() + 0.0);
  return buffer;
}

// UR's TCP setting: [x, y, z] m and a rotation vector, rad.
std::string UrTcp(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.linear());
  const Eigen::Vector3d r = aa.axis() * aa.angle();
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "p[%.9g, %.9g, %.9g, %.9g, %.9g, %.9g]", T.translation().x() + 0.0,
                T.translation().y() + 0.0, T.translation().z() + 0.0, r.x() + 0.0, r.y() + 0.0, r.z() + 0.0);
  return buffer;
}

bool IsIdentity(const Eigen::Isometry3d& T) { return T.matrix().isIdentity(1e-12); }

std::vector<std::string> DroppedItems(const Robot& robot, const Eigen::Isometry3d& base,
                                      const Eigen::Isometry3d& tool) {
  std::vector<std::string> dropped;
  if (!IsIdentity(base)) {
    dropped.push_back("base not held (the file starts at the controller's base, base_link_inertia): T_meas_base " +
                      PoseWords(base) + ", the installation's place in the measurement frame");
  }
  if (!IsIdentity(tool)) {
    dropped.push_back("tool not held (tool0 is wrist_3_link): set it as the controller's TCP, " + UrTcp(tool) +
                      " (m, rotation vector rad); " + PoseWords(tool));
  }
  if (robot.drives) dropped.push_back("drives not held (ratio, counts_per_rev, encoder_zero): the controller keeps its own");
  if (robot.coupling.size() && !robot.coupling.isIdentity(0.0)) {
    dropped.push_back("coupling not held: the controller reads each joint as it is");
  }
  std::string names;  // the joint error terms that move a joint (all-zero ones are not lost)
  for (const auto& term : robot.joint_errors.terms) {
    if (term.coefficients.size() == 0 || term.coefficients.cwiseAbs().maxCoeff() == 0.0) continue;
    names += (names.empty() ? "" : ", ") + JointErrorTerm::TypeName(term.type) + " " + std::to_string(term.joint + 1);
  }
  if (!names.empty()) dropped.push_back("joint errors not held (" + names + "): the file has no joint-level terms");
  return dropped;
}

using Row = std::array<double, 6>;  // x, y, z, roll, pitch, yaw

Row RowOf(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d p = T.translation(), rpy = RpyFromRotation(T.linear());
  return {p.x(), p.y(), p.z(), rpy.x(), rpy.y(), rpy.z()};
}

// A robot in the urdf convention whose axes are its joint frames' z and whose offsets are 0 has the
// file's rows as they are: written unchanged, a UR file read and written back keeps its numbers.
bool HasUrRows(const KinematicModel& model) {
  if (model.convention() != "urdf") return false;
  for (int i = 1; i <= model.dof(); ++i) {
    const std::string n = std::to_string(i);
    if (model.Parameter("axis_azimuth_" + n) != 0.0 || model.Parameter("axis_tilt_" + n) != 0.0 ||
        model.Parameter("offset_" + n) != 0.0) {
      return false;
    }
  }
  return true;
}

std::string FileText(const std::vector<Row>& rows, const std::vector<std::string>& dropped,
                     const std::string& source_name) {
  std::ostringstream body;
  body << "kinematics:\n";
  for (int i = 0; i < 6; ++i) {
    body << "  " << kJoints[i] << ":\n";
    for (int k = 0; k < 6; ++k) body << "    " << kKeys[k] << ": " << FormatExact(rows[i][k] + 0.0) << "\n";
  }
  // Not the controller's checksum (kincal cannot compute that): the driver will say the calibration
  // differs from the robot's, which is true. A digest of the numbers tells files apart.
  uint64_t digest = 1469598103934665603ull;
  for (char c : body.str()) digest = (digest ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  std::ostringstream out;
  out << "# UR kinematics (ur_description's kinematics YAML) written by kincal from " << source_name << ".\n"
      << "# Per joint: the origin in its parent's frame (m; roll, pitch, yaw in rad about fixed axes),\n"
      << "# then the rotation about z; from base_link_inertia (the controller's base) to wrist_3_link (tool0).\n";
  if (dropped.empty()) out << "# Everything in the robot file is held.\n";
  for (const auto& line : dropped) out << "# " << line << "\n";
  out << body.str() << "  hash: kincal_" << std::hex << digest << "\n";
  return out.str();
}

}  // namespace

bool LooksLikeUrKinematics(const std::string& path) {
  if (EndsWith(path, ".yaml") || EndsWith(path, ".yml")) return true;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    return root.IsMap() && root["kinematics"];
  } catch (const std::exception&) {
    return false;
  }
}

Robot ReadUrKinematics(const std::string& path) { return ParseUrKinematics(ReadFileToString(path), path); }

Robot ParseUrKinematics(const std::string& text, const std::string& source_name) {
  const robot_file::Reader r(source_name);
  const YAML::Node root = Load(text, source_name);
  if (!root.IsMap() || !root["kinematics"]) {
    r.Fail(root, "expected a map with the key 'kinematics' (a UR kinematics YAML)");
  }
  const YAML::Node k = root["kinematics"];
  r.ExpectMap(k, "kinematics");
  r.CheckKeys(k, {"shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3", "hash"}, "kinematics");
  auto model = std::make_unique<UrdfModel>(6);
  for (int i = 0; i < 6; ++i) {
    const YAML::Node joint = k[kJoints[i]];
    if (!joint) r.Fail(k, std::string("kinematics lacks '") + kJoints[i] + "'");
    r.ExpectMap(joint, std::string("kinematics.") + kJoints[i]);
    r.CheckKeys(joint, {"x", "y", "z", "roll", "pitch", "yaw"}, std::string("kinematics.") + kJoints[i]);
    for (int j = 0; j < 6; ++j) {
      const std::string what = std::string(kJoints[i]) + "." + kKeys[j];
      if (!joint[kKeys[j]]) r.Fail(joint, std::string("kinematics.") + kJoints[i] + " lacks '" + kKeys[j] + "'");
      const double value = r.Number(joint[kKeys[j]], what);
      if (!std::isfinite(value)) r.Fail(joint[kKeys[j]], "expected a finite number for " + what);
      model->SetParameter(std::string(kKeys[j]) + "_" + std::to_string(i + 1), value);
    }
  }
  Robot robot(Stem(source_name), std::move(model));
  for (int i = 0; i < 6; ++i) {
    const double limit = i == 2 ? M_PI : 2 * M_PI;  // ur_description's joint_limits.yaml
    robot.limits.emplace_back(-limit, limit);
  }
  robot.length_unit = LengthUnit("m");
  robot.angle_unit = AngleUnit("rad");
  return robot;
}

UrKinematicsExport ExportUrKinematics(const Robot& robot, const std::string& source_name) {
  const KinematicModel& model = robot.model();
  bool all_revolute = model.dof() == 6;
  for (int i = 0; all_revolute && i < 6; ++i) all_revolute = model.joint_type(i) == JointType::kRevolute;
  if (!all_revolute) {
    throw std::invalid_argument("a UR kinematics file holds 6 revolute joints; the robot has " +
                                std::to_string(model.dof()) + " joints" + (model.dof() == 6 ? ", not all revolute" : ""));
  }
  const Eigen::Isometry3d base = model.base();
  Eigen::Isometry3d tool = model.tool();
  std::vector<Row> rows;
  if (HasUrRows(model)) {
    for (int i = 1; i <= 6; ++i) {
      Row row;
      for (int k = 0; k < 6; ++k) row[k] = model.Parameter(std::string(kKeys[k]) + "_" + std::to_string(i));
      rows.push_back(row);
    }
  } else {
    std::vector<Eigen::Isometry3d> M = JointFramesAtZero(model);
    // The flange frame (frame n) is the last joint's frame when it lies on that axis (z along it): then
    // the tool stays the robot's own (a POE model's joint frames sit anywhere along their axes).
    const Eigen::Isometry3d flange = model.ForwardKinematics(Eigen::VectorXd::Zero(6)) * model.tool().inverse();
    const Eigen::Vector3d axis = M[5].linear().col(2), d = flange.translation() - M[5].translation();
    if ((flange.linear().col(2) - axis).norm() < 1e-12 && (d - axis * axis.dot(d)).norm() < 1e-12) M[5] = flange;
    for (int i = 0; i < 6; ++i) rows.push_back(RowOf((i == 0 ? base : M[i - 1]).inverse() * M[i]));
    tool = M[5].inverse() * model.ForwardKinematics(Eigen::VectorXd::Zero(6));
  }
  UrKinematicsExport out;
  out.dropped = DroppedItems(robot, base, tool);
  out.text = FileText(rows, out.dropped, source_name);
  Robot file = ParseUrKinematics(out.text, source_name);
  Robot held = robot.WithModel(file.model().Clone());
  held.model().SetBase(base);
  held.model().SetTool(tool);
  held.drives.reset();
  held.coupling.resize(0, 0);
  held.joint_errors = JointErrors();
  held.urdf.reset();
  out.held = std::move(held);
  return out;
}

}  // namespace kincal
