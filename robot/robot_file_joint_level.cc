// Robot-file keys of the joint level (DESIGN.md "File contracts (v1)"):
//
//   velocity_limits: [250, 250, 250, 320, 320, 420]   # angle unit per second (length unit for prismatic)
//   coupling: [[1, 0, 0], [0, 1, 0], [0, 1, 1]]       # actual joints = C x readings
//   gravity: [0, 0, -1]                               # direction in the base frame
//   joint_errors:
//     - {joint: 2, type: gravity}                     # identified files add `coefficients: {key: value}`
//     - {joint: 1, type: harmonic, orders: [1, 2]}
//     - {joint: 1, type: approach}
//
// Coefficients are in the file's angle unit per unit of their regressor (models/joint_errors.h): angle
// for gravity link<j>_x/_y/_z, harmonic and backlash terms; angle per length for gravity link<j>; seconds
// for approach terms (angle per angle-per-second).
#include <map>
#include <sstream>

#include "robot/robot_file_reader.h"

namespace kincal::robot_file {
namespace {

Unit CoefficientUnit(JointErrorTerm::Type type, const std::string& key, const Unit& length, const Unit& angle) {
  switch (JointErrorTerm::KindOf(type, key)) {
    case JointErrorTerm::CoefficientKind::kTime:
      return {"s", 1.0};
    case JointErrorTerm::CoefficientKind::kAnglePerLength:
      return {angle.name + "/" + length.name, angle.to_si / length.to_si};
    case JointErrorTerm::CoefficientKind::kAngle:
      break;
  }
  return angle;
}

std::string List(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

int WholeNumber(const Reader& r, const YAML::Node& node, const std::string& what) {
  const double v = r.Number(node, what);
  if (v != static_cast<double>(static_cast<long long>(v)) || std::abs(v) > 1e6)
    r.Fail(node, "expected a whole number for " + what);
  return static_cast<int>(v);
}

void ReadJointErrors(const Reader& r, const YAML::Node& list, Robot* robot) {
  if (!list.IsSequence()) r.Fail(list, "expected 'joint_errors' to be a list of {joint, type, ...} maps");
  const int n = robot->dof();
  std::vector<std::map<std::string, std::pair<double, YAML::Node>>> given;
  for (const auto& item : list) {
    r.ExpectMap(item, "a joint_errors entry");
    r.CheckKeys(item, {"joint", "type", "orders", "coefficients"}, "a joint_errors entry");
    if (!item["joint"]) r.Fail(item, "a joint_errors entry lacks 'joint' (1.." + std::to_string(n) + ")");
    if (!item["type"]) r.Fail(item, "a joint_errors entry lacks 'type' (gravity, harmonic, backlash or approach)");
    JointErrorTerm term;
    term.joint = WholeNumber(r, item["joint"], "joint") - 1;
    if (term.joint < 0 || term.joint >= n) r.Fail(item["joint"], "expected a joint 1.." + std::to_string(n));
    try {
      term.type = JointErrorTerm::TypeFromName(r.String(item["type"], "type"));
    } catch (const std::invalid_argument& e) {
      r.Fail(item["type"], e.what());
    }
    if (item["orders"]) {
      if (term.type != JointErrorTerm::Type::kHarmonic) r.Fail(item["orders"], "only harmonic terms take 'orders'");
      if (!item["orders"].IsSequence()) r.Fail(item["orders"], "expected a list of orders, e.g. [1, 2]");
      for (const auto& h : item["orders"]) term.orders.push_back(WholeNumber(r, h, "a harmonic order"));
    }
    std::map<std::string, std::pair<double, YAML::Node>> coefficients;
    if (item["coefficients"]) {
      r.ExpectMap(item["coefficients"], "coefficients");
      for (const auto& kv : item["coefficients"]) {
        const std::string key = r.String(kv.first, "a coefficient key");
        const Unit u = CoefficientUnit(term.type, key, robot->length_unit, robot->angle_unit);
        coefficients[key] = {r.Number(kv.second, "coefficient " + key) * u.to_si, kv.first};
      }
    }
    given.push_back(coefficients);
    robot->joint_errors.terms.push_back(term);
  }
  try {
    robot->joint_errors.Bind(robot->model());
  } catch (const std::invalid_argument& e) {
    r.Fail(list, std::string("joint_errors: ") + e.what());
  }
  for (size_t t = 0; t < given.size(); ++t) {
    JointErrorTerm& term = robot->joint_errors.terms[t];
    for (const auto& [key, value] : given[t]) {
      const auto it = std::find(term.keys.begin(), term.keys.end(), key);
      if (it == term.keys.end()) {
        r.Fail(value.second, "unknown coefficient '" + key + "' of this " + JointErrorTerm::TypeName(term.type) +
                                 " term (expected one of " + List(term.keys) + ")");
      }
      term.coefficients[it - term.keys.begin()] = value.first;
    }
  }
}

}  // namespace

void ReadJointLevel(const Reader& r, const YAML::Node& root, Robot* robot) {
  const int n = robot->dof();
  const Unit& length = robot->length_unit;
  const Unit& angle = robot->angle_unit;
  if (root["velocity_limits"]) {
    const auto v = r.Numbers(root["velocity_limits"], "velocity_limits", n);
    robot->velocity_limits.resize(n);
    for (int i = 0; i < n; ++i) {
      if (!(v[i] > 0.0)) r.Fail(root["velocity_limits"][i], "expected a positive velocity limit");
      robot->velocity_limits[i] =
          v[i] * (robot->model().joint_type(i) == JointType::kRevolute ? angle.to_si : length.to_si);
    }
  }
  if (root["coupling"]) {
    const YAML::Node c = root["coupling"];
    if (!c.IsSequence() || static_cast<int>(c.size()) != n) {
      r.Fail(c, "expected 'coupling' to list " + std::to_string(n) + " rows of " + std::to_string(n) + " numbers");
    }
    robot->coupling.resize(n, n);
    for (int i = 0; i < n; ++i) {
      const auto row = r.Numbers(c[i], "coupling row " + std::to_string(i + 1), n);
      for (int j = 0; j < n; ++j) robot->coupling(i, j) = row[j];
    }
  }
  if (root["gravity"]) {
    const auto g = r.Numbers(root["gravity"], "gravity", 3);
    robot->gravity = Eigen::Vector3d(g[0], g[1], g[2]);
    if (!(robot->gravity->norm() > 0.0)) r.Fail(root["gravity"], "expected a non-zero gravity direction");
  }
  if (root["joint_errors"]) ReadJointErrors(r, root["joint_errors"], robot);
  try {
    robot->ValidateJointLevel();
  } catch (const std::invalid_argument& e) {
    const char* keys[] = {"coupling", "velocity_limits", "gravity", "joint_errors"};
    YAML::Node where = root;
    for (const char* k : keys) {
      if (std::string(e.what()).rfind(k, 0) == 0 && root[k]) where = root[k];
    }
    r.Fail(where, e.what());
  }
}

std::string JointLevelToYaml(const Robot& robot) {
  std::ostringstream out;
  const int n = robot.dof();
  const Unit& length = robot.length_unit;
  const Unit& angle = robot.angle_unit;
  if (robot.velocity_limits.size() != 0) {
    std::vector<std::string> v;
    for (int i = 0; i < n; ++i) {
      v.push_back(
          FormatInUnit(robot.velocity_limits[i], robot.model().joint_type(i) == JointType::kRevolute ? angle : length));
    }
    out << "velocity_limits: " << List(v) << "\n";
  }
  if (robot.coupling.size() != 0) {
    std::vector<std::string> rows;
    for (int i = 0; i < n; ++i) {
      std::vector<std::string> row;
      for (int j = 0; j < n; ++j) row.push_back(FormatExact(robot.coupling(i, j)));
      rows.push_back(List(row));
    }
    out << "coupling: " << List(rows) << "\n";
  }
  if (robot.gravity) {
    out << "gravity: "
        << List({FormatExact(robot.gravity->x()), FormatExact(robot.gravity->y()), FormatExact(robot.gravity->z())})
        << "\n";
  }
  if (!robot.joint_errors.empty()) {
    out << "joint_errors:\n";
    for (const auto& t : robot.joint_errors.terms) {
      out << "  - {joint: " << t.joint + 1 << ", type: " << JointErrorTerm::TypeName(t.type);
      if (!t.orders.empty()) {
        std::vector<std::string> orders;
        for (int h : t.orders) orders.push_back(std::to_string(h));
        out << ", orders: " << List(orders);
      }
      if (!t.coefficients.isZero(0.0)) {
        std::vector<std::string> items;
        for (size_t k = 0; k < t.keys.size(); ++k) {
          const Unit u = CoefficientUnit(t.type, t.keys[k], length, angle);
          items.push_back(t.keys[k] + ": " + FormatInUnit(t.coefficients[static_cast<Eigen::Index>(k)], u));
        }
        std::string map = List(items);
        out << ", coefficients: {" << map.substr(1, map.size() - 2) << "}";
      }
      out << "}\n";
    }
  }
  return out.str();
}

}  // namespace kincal::robot_file
