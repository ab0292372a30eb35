#include "robot/robot_file.h"

#include <cctype>
#include <cstdio>

#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "robot/robot_file_reader.h"
#include "models/model_factory.h"

namespace kincal {
namespace {

using robot_file::Reader;

// Sets the six pose parameters directly, so that file values survive without an rpy round trip.
void SetPoseParameters(const Reader& r, const YAML::Node& node, const std::string& prefix, const Unit& length,
                       const Unit& angle, KinematicModel* model) {
  r.ExpectMap(node, prefix);
  r.CheckKeys(node, {"xyz", "rpy"}, prefix);
  const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  if (node["xyz"]) {
    const auto v = r.Numbers(node["xyz"], prefix + ".xyz", 3);
    for (int i = 0; i < 3; ++i) model->SetParameter(prefix + "_" + keys[i], v[i] * length.to_si);
  }
  if (node["rpy"]) {
    const auto v = r.Numbers(node["rpy"], prefix + ".rpy", 3);
    for (int i = 0; i < 3; ++i) model->SetParameter(prefix + "_" + keys[i + 3], v[i] * angle.to_si);
  }
}

// The file's units (required): lengths and angles of every value in it.
std::pair<Unit, Unit> ReadUnits(const Reader& r, const YAML::Node& root, const std::string& source) {
  Unit length = LengthUnit("mm"), angle = AngleUnit("deg");
  if (!root["units"]) ThrowInputError(source, 1, 1, "missing key 'units' (e.g. units: {length: mm, angle: deg})");
  const YAML::Node units = root["units"];
  r.ExpectMap(units, "units");
  r.CheckKeys(units, {"length", "angle"}, "units");
  try {
    if (units["length"]) length = LengthUnit(r.String(units["length"], "units.length"));
    if (units["angle"]) angle = AngleUnit(r.String(units["angle"], "units.angle"));
  } catch (const std::invalid_argument& e) {
    r.Fail(units, e.what());
  }
  return {length, angle};
}

// The model of `convention` with the joints' rows, base and tool.
std::unique_ptr<KinematicModel> ReadModel(const Reader& r, const YAML::Node& root, const std::string& source,
                                          const Unit& length, const Unit& angle) {
  if (!root["convention"]) {
    ThrowInputError(source, 1, 1, "missing key 'convention' (mdh, dh, hayati, poe or urdf)");
  }
  if (!root["joints"]) ThrowInputError(source, 1, 1, "missing key 'joints'");
  const std::string convention = r.String(root["convention"], "convention");
  const YAML::Node joints = root["joints"];
  if (!joints.IsSequence() || joints.size() == 0) r.Fail(joints, "expected 'joints' to be a non-empty list of rows");

  std::vector<JointType> types;
  for (const auto& row : joints) {
    r.ExpectMap(row, "a joint row");
    JointType type = JointType::kRevolute;
    if (row["type"]) {
      const std::string t = r.String(row["type"], "type");
      if (t == "prismatic")
        type = JointType::kPrismatic;
      else if (t != "revolute")
        r.Fail(row["type"], "expected type revolute or prismatic, got '" + t + "'");
    }
    types.push_back(type);
  }
  std::unique_ptr<KinematicModel> model;
  try {
    model = MakeModel(convention, types);
  } catch (const std::invalid_argument& e) {
    r.Fail(root["convention"], e.what());
  }
  const std::vector<std::string> keys = model->RowKeys();
  std::set<std::string> allowed(keys.begin(), keys.end());
  allowed.insert("type");
  for (size_t i = 0; i < joints.size(); ++i) {
    const YAML::Node row = joints[i];
    r.CheckKeys(row, allowed, "joint row " + std::to_string(i + 1));
    for (const auto& key : keys) {
      // Hayati's beta and a POE row's theta default to 0 (an MDH table reads as a Hayati model unchanged).
      // A URDF row's offset (no URDF field) defaults to 0 as well.
      if (!row[key] &&
          (key == "beta" || (convention == "poe" && key == "theta") || (convention == "urdf" && key == "offset"))) {
        continue;
      }
      if (!row[key]) r.Fail(row, "joint row " + std::to_string(i + 1) + " lacks '" + key + "'");
      const std::string name = key + "_" + std::to_string(i + 1);
      const int index = model->ParameterIndex(name);
      const bool is_angle = model->parameter_info()[index].kind == ParameterInfo::Kind::kAngle;
      model->SetParameter(name, r.Number(row[key], name) * (is_angle ? angle.to_si : length.to_si));
    }
  }
  if (root["base"]) SetPoseParameters(r, root["base"], "base", length, angle, model.get());
  if (root["tool"]) SetPoseParameters(r, root["tool"], "tool", length, angle, model.get());
  return model;
}

DriveModel ReadDrives(const Reader& r, const YAML::Node& d, int n) {
  r.ExpectMap(d, "drives");
  r.CheckKeys(d, {"ratio", "counts_per_rev", "encoder_zero"}, "drives");
  if (!d["ratio"]) r.Fail(d, "drives lacks 'ratio'");
  if (!d["counts_per_rev"]) r.Fail(d, "drives lacks 'counts_per_rev'");
  DriveModel drives;
  const auto to_vector = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())).eval();
  };
  drives.ratio = to_vector(r.Numbers(d["ratio"], "drives.ratio", n));
  drives.counts_per_rev = to_vector(r.Numbers(d["counts_per_rev"], "drives.counts_per_rev", n));
  drives.encoder_zero =
      d["encoder_zero"] ? to_vector(r.Numbers(d["encoder_zero"], "drives.encoder_zero", n)) : Eigen::VectorXd::Zero(n);
  try {
    drives.Validate(n);
  } catch (const std::invalid_argument& e) {
    r.Fail(d, e.what());
  }
  return drives;
}

// limits, markers, sessions and urdf, each optional.
void ReadLimitsMarkersSessions(const Reader& r, const YAML::Node& root, Robot* robot) {
  const int n = robot->dof();
  const Unit& length = robot->length_unit;
  const Unit& angle = robot->angle_unit;
  if (root["limits"]) {
    const YAML::Node l = root["limits"];
    if (!l.IsSequence() || static_cast<int>(l.size()) != n) {
      r.Fail(l, "expected 'limits' to list " + std::to_string(n) + " [min, max] pairs");
    }
    for (int i = 0; i < n; ++i) {
      const auto v = r.Numbers(l[i], "limits of joint " + std::to_string(i + 1), 2);
      const double scale = robot->model().joint_type(i) == JointType::kRevolute ? angle.to_si : length.to_si;
      if (!(v[0] < v[1])) r.Fail(l[i], "expected min < max for the limits of joint " + std::to_string(i + 1));
      robot->limits.emplace_back(v[0] * scale, v[1] * scale);
    }
  }
  if (root["markers"]) {
    const YAML::Node m = root["markers"];
    r.ExpectMap(m, "markers");
    for (const auto& kv : m) {
      const auto v = r.Numbers(kv.second, "marker " + kv.first.Scalar(), 3);
      robot->markers[kv.first.Scalar()] = Eigen::Vector3d(v[0], v[1], v[2]) * length.to_si;
    }
  }
  if (root["sessions"]) {
    const YAML::Node s = root["sessions"];
    r.ExpectMap(s, "sessions");
    for (const auto& kv : s) {
      const double id = r.Number(kv.first, "a session id");
      if (id != static_cast<int>(id)) r.Fail(kv.first, "expected an integer session id");
      robot->session_bases[static_cast<int>(id)] = r.Pose(kv.second, "session " + kv.first.Scalar(), length, angle);
    }
  }
}

Robot::UrdfSource ReadUrdfSource(const Reader& r, const YAML::Node& u, int n) {
  r.ExpectMap(u, "urdf");
  r.CheckKeys(u, {"source", "base", "tip", "joints"}, "urdf");
  for (const char* key : {"source", "base", "tip", "joints"}) {
    if (!u[key]) r.Fail(u, std::string("urdf lacks '") + key + "'");
  }
  Robot::UrdfSource source{
      r.String(u["source"], "urdf.source"), r.String(u["base"], "urdf.base"), r.String(u["tip"], "urdf.tip"), {}};
  if (!u["joints"].IsSequence() || static_cast<int>(u["joints"].size()) != n) {
    r.Fail(u["joints"], "expected urdf.joints to name the " + std::to_string(n) + " moving joints");
  }
  for (const auto& j : u["joints"]) source.joints.push_back(r.String(j, "a urdf joint name"));
  return source;
}

}  // namespace

Robot ParseRobotYaml(const std::string& text, const std::string& source) {
  Reader r(source);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    ThrowInputError(source, e.mark.line + 1, e.mark.column + 1, "invalid YAML: " + e.msg);
  }
  if (!root.IsMap()) ThrowInputError(source, 1, 1, "expected a robot description (a YAML map)");
  r.CheckKeys(root,
              {"name", "convention", "units", "joints", "drives", "limits", "base", "tool", "markers", "sessions",
               "velocity_limits", "coupling", "gravity", "joint_errors", "urdf", "fixtures"},
              "the robot file");
  const auto [length, angle] = ReadUnits(r, root, source);
  std::unique_ptr<KinematicModel> model = ReadModel(r, root, source, length, angle);
  const int n = model->dof();
  Robot robot(root["name"] ? r.String(root["name"], "name") : std::string("robot"), std::move(model));
  robot.length_unit = length;
  robot.angle_unit = angle;
  if (root["drives"]) robot.drives = ReadDrives(r, root["drives"], n);
  ReadLimitsMarkersSessions(r, root, &robot);
  if (root["urdf"]) robot.urdf = ReadUrdfSource(r, root["urdf"], n);
  robot_file::ReadJointLevel(r, root, &robot);
  robot_file::ReadFixtures(r, root, &robot);
  return robot;
}

Robot ReadRobotFile(const std::string& path) { return ParseRobotYaml(ReadFileToString(path), path); }

namespace {

std::string List(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

std::string PoseText(const KinematicModel& model, const std::string& prefix, const Unit& length, const Unit& angle) {
  const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::vector<std::string> xyz, rpy;
  for (int i = 0; i < 3; ++i) xyz.push_back(FormatInUnit(model.Parameter(prefix + "_" + keys[i]), length));
  for (int i = 3; i < 6; ++i) rpy.push_back(FormatInUnit(model.Parameter(prefix + "_" + keys[i]), angle));
  return "{xyz: " + List(xyz) + ", rpy: " + List(rpy) + "}";
}

std::string IsometryText(const Eigen::Isometry3d& T, const Unit& length, const Unit& angle) {
  const Eigen::Vector3d rpy = RpyFromRotation(T.linear());
  std::vector<std::string> xyz, r;
  for (int i = 0; i < 3; ++i) xyz.push_back(FormatInUnit(T.translation()[i], length));
  for (int i = 0; i < 3; ++i) r.push_back(FormatInUnit(rpy[i], angle));
  return "{xyz: " + List(xyz) + ", rpy: " + List(r) + "}";
}

}  // namespace

std::string robot_file::YamlString(const std::string& text) {
  bool plain = !text.empty() && text != "null" && text != "Null" && text != "NULL" && text != "~";
  for (size_t i = 0; i < text.size() && plain; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    plain = std::isalnum(c) || c == '_' || (i > 0 && (c == '-' || c == '.'));
  }
  if (plain) return text;
  std::string out = "\"";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      out += escape;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string RobotToYaml(const Robot& robot) {
  const KinematicModel& model = robot.model();
  const Unit& L = robot.length_unit;
  const Unit& A = robot.angle_unit;
  std::ostringstream out;
  out << "name: " << robot_file::YamlString(robot.name) << "\n";
  out << "convention: " << model.convention() << "\n";
  out << "units: {length: " << L.name << ", angle: " << A.name << "}\n";
  out << "joints:\n";
  for (int i = 0; i < model.dof(); ++i) {
    out << "  - {";
    bool first = true;
    for (const auto& key : model.RowKeys()) {
      const std::string name = key + "_" + std::to_string(i + 1);
      const int index = model.ParameterIndex(name);
      const bool is_angle = model.parameter_info()[index].kind == ParameterInfo::Kind::kAngle;
      out << (first ? "" : ", ") << key << ": " << FormatInUnit(model.Parameters()[index], is_angle ? A : L);
      first = false;
    }
    if (model.joint_type(i) == JointType::kPrismatic) out << ", type: prismatic";
    out << "}\n";
  }
  if (robot.drives) {
    const DriveModel& d = *robot.drives;
    std::vector<std::string> ratio, counts, zero;
    bool any_zero = false;
    for (int i = 0; i < d.dof(); ++i) {
      ratio.push_back(FormatExact(d.ratio[i]));
      counts.push_back(FormatExact(d.counts_per_rev[i]));
      zero.push_back(FormatExact(d.encoder_zero[i]));
      any_zero = any_zero || d.encoder_zero[i] != 0.0;
    }
    out << "drives:\n  ratio: " << List(ratio) << "\n  counts_per_rev: " << List(counts) << "\n";
    if (any_zero) out << "  encoder_zero: " << List(zero) << "\n";
  }
  if (!robot.limits.empty()) {
    out << "limits: [";
    for (size_t i = 0; i < robot.limits.size(); ++i) {
      const Unit& u = model.joint_type(static_cast<int>(i)) == JointType::kRevolute ? A : L;
      out << (i ? ", " : "") << "[" << FormatInUnit(robot.limits[i].first, u) << ", "
          << FormatInUnit(robot.limits[i].second, u) << "]";
    }
    out << "]\n";
  }
  out << robot_file::JointLevelToYaml(robot);
  out << "base: " << PoseText(model, "base", L, A) << "\n";
  out << "tool: " << PoseText(model, "tool", L, A) << "\n";
  if (!robot.markers.empty()) {
    out << "markers:\n";
    for (const auto& [id, p] : robot.markers) {
      out << "  " << robot_file::YamlString(id) << ": "
          << List({FormatInUnit(p.x(), L), FormatInUnit(p.y(), L), FormatInUnit(p.z(), L)}) << "\n";
    }
  }
  if (robot.urdf) {
    // Names are written as YAML double-quoted strings (URDF names may hold any character).
    auto quoted = [](const std::string& text) {
      std::string q = "\"";
      for (char c : text) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
      return q + "\"";
    };
    std::vector<std::string> joints;
    for (const auto& j : robot.urdf->joints) joints.push_back(quoted(j));
    out << "urdf: {source: " << quoted(robot.urdf->path) << ", base: " << quoted(robot.urdf->base_link)
        << ", tip: " << quoted(robot.urdf->tip_link) << ", joints: " << List(joints) << "}\n";
  }
  if (!robot.session_bases.empty()) {
    out << "sessions:\n";
    for (const auto& [id, T] : robot.session_bases) out << "  " << id << ": " << IsometryText(T, L, A) << "\n";
  }
  out << robot_file::FixturesToYaml(robot);
  return out.str();
}

void WriteRobotFile(const Robot& robot, const std::string& path) { WriteFileAtomically(path, RobotToYaml(robot)); }

}  // namespace kincal
