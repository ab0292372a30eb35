#pragma once
// The YAML reading helpers of robot files (robot/robot_file.cc and robot_file_joint_level.cc):
// every failure names the file, line and column. Internal to the robot-file reader.
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

#include "framework/error.h"
#include "framework/math.h"
#include "robot/robot.h"
#include "framework/units.h"

namespace kincal::robot_file {

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& what) const {
    const YAML::Mark mark = node.Mark();
    if (mark.is_null()) ThrowInputError(source_, 0, 0, what);
    ThrowInputError(source_, mark.line + 1, mark.column + 1, what);
  }

  void ExpectMap(const YAML::Node& node, const std::string& what) const {
    if (!node.IsMap()) Fail(node, "expected " + what + " to be a map");
  }

  void CheckKeys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& where) const {
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (!allowed.count(key)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Fail(kv.first, "unknown key '" + key + "' in " + where + " (expected " + list + ")");
      }
    }
  }

  double Number(const YAML::Node& node, const std::string& what) const {
    double value = 0.0;
    if (!node.IsScalar() || !ParseDouble(node.Scalar(), &value)) Fail(node, "expected a number for " + what);
    return value;
  }

  std::string String(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) Fail(node, "expected a string for " + what);
    return node.Scalar();
  }

  std::vector<double> Numbers(const YAML::Node& node, const std::string& what, int expected) const {
    if (!node.IsSequence()) Fail(node, "expected a list of numbers for " + what);
    if (expected >= 0 && static_cast<int>(node.size()) != expected) {
      Fail(node,
           "expected " + std::to_string(expected) + " numbers for " + what + ", got " + std::to_string(node.size()));
    }
    std::vector<double> out;
    for (const auto& item : node) out.push_back(Number(item, what));
    return out;
  }

  Eigen::Isometry3d Pose(const YAML::Node& node, const std::string& what, const Unit& length, const Unit& angle) const {
    ExpectMap(node, what);
    CheckKeys(node, {"xyz", "rpy"}, what);
    Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
    if (node["xyz"]) {
      const auto v = Numbers(node["xyz"], what + ".xyz", 3);
      xyz = Eigen::Vector3d(v[0], v[1], v[2]) * length.to_si;
    }
    if (node["rpy"]) {
      const auto v = Numbers(node["rpy"], what + ".rpy", 3);
      rpy = Eigen::Vector3d(v[0], v[1], v[2]) * angle.to_si;
    }
    return PoseFromXyzRpy(xyz, rpy);
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

// The joint-level keys of file contract v1 (DESIGN.md): velocity_limits, coupling, gravity, joint_errors
// (robot_file_joint_level.cc). Reading needs the robot's model and units in place.
void ReadJointLevel(const Reader& r, const YAML::Node& root, Robot* robot);
std::string JointLevelToYaml(const Robot& robot);

// The `fixtures:` section (robot_file_fixtures.cc), in the robot's units.
void ReadFixtures(const Reader& r, const YAML::Node& root, Robot* robot);
std::string FixturesToYaml(const Robot& robot);

// A name as YAML that reads back to the same string: plain when it is a simple word, double-quoted with
// escapes otherwise ("a: b", "#1", "- x", "null", "", leading spaces, control bytes).
std::string YamlString(const std::string& text);

}  // namespace kincal::robot_file
