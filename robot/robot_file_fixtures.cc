// The robot file's `fixtures:` section (robot/fixtures.h):
//   fixtures:
//     pivots: {P1: {xyz: [700, 0, 300]}, P2: {xyz: [0, 700, 300], sd: 1}}
//     planes: {table: {normal: [0, 0, 1], offset: 300, sd: 0.5, sd_angle: 0.1}}
//     points: {socket: {xyz: [500, 200, 100], sd: 2}}
// Lengths (xyz, offset, sd) in the file's length unit, sd_angle in its angle unit, the normal unitless.
#include <cmath>
#include <sstream>

#include "framework/units.h"
#include "robot/robot_file_reader.h"

namespace kincal::robot_file {
namespace {

const char* SectionName(Fixture::Type type) {
  return type == Fixture::Type::kPivot ? "pivots" : type == Fixture::Type::kPlane ? "planes" : "points";
}

// A non-negative sd, or 0 when absent.
double ReadSd(const Reader& r, const YAML::Node& node, const std::string& what, double to_si) {
  if (!node) return 0.0;
  const double v = r.Number(node, what);
  if (!(v >= 0.0)) r.Fail(node, "expected " + what + " >= 0");
  return v * to_si;
}

Fixture ReadOne(const Reader& r, Fixture::Type type, const YAML::Node& key, const YAML::Node& node,
                const Robot& robot) {
  const std::string name = r.String(key, "a fixture name");
  const std::string where = std::string(SectionName(type)) + "." + name;
  r.ExpectMap(node, where);
  Fixture f;
  f.type = type;
  f.name = name;
  const double length = robot.length_unit.to_si;
  if (type == Fixture::Type::kPlane) {
    r.CheckKeys(node, {"normal", "offset", "sd", "sd_angle"}, where);
    if (!node["normal"] || !node["offset"]) r.Fail(node, where + " needs 'normal' and 'offset'");
    const auto n = r.Numbers(node["normal"], where + ".normal", 3);
    f.normal = Eigen::Vector3d(n[0], n[1], n[2]);
    if (std::abs(f.normal.norm() - 1.0) > 1e-6) r.Fail(node["normal"], "expected a unit normal for " + where);
    f.offset = r.Number(node["offset"], where + ".offset") * length;
    f.sd_angle = ReadSd(r, node["sd_angle"], where + ".sd_angle", robot.angle_unit.to_si);
  } else {
    r.CheckKeys(node, {"xyz", "sd"}, where);
    if (!node["xyz"]) r.Fail(node, where + " needs 'xyz'");
    const auto v = r.Numbers(node["xyz"], where + ".xyz", 3);
    f.position = Eigen::Vector3d(v[0], v[1], v[2]) * length;
  }
  f.sd = ReadSd(r, node["sd"], where + ".sd", length);
  f.known = f.sd == 0.0 && f.sd_angle == 0.0;
  return f;
}

}  // namespace

void ReadFixtures(const Reader& r, const YAML::Node& root, Robot* robot) {
  const YAML::Node section = root["fixtures"];
  if (!section) return;
  r.ExpectMap(section, "fixtures");
  r.CheckKeys(section, {"pivots", "planes", "points"}, "fixtures");
  for (Fixture::Type type : {Fixture::Type::kPivot, Fixture::Type::kPlane, Fixture::Type::kPoint}) {
    const YAML::Node items = section[SectionName(type)];
    if (!items) continue;
    r.ExpectMap(items, std::string("fixtures.") + SectionName(type));
    for (const auto& kv : items) {
      Fixture f = ReadOne(r, type, kv.first, kv.second, *robot);
      if (robot->fixtures.Find(type, f.name)) r.Fail(kv.first, FixtureTypeName(type) + " '" + f.name + "' given twice");
      robot->fixtures.items.push_back(std::move(f));
    }
  }
}

std::string FixturesToYaml(const Robot& robot) {
  if (robot.fixtures.empty()) return "";
  const Unit& L = robot.length_unit;
  std::ostringstream out;
  out << "fixtures:\n";
  for (Fixture::Type type : {Fixture::Type::kPivot, Fixture::Type::kPlane, Fixture::Type::kPoint}) {
    bool first = true;
    for (const Fixture& f : robot.fixtures.items) {
      if (f.type != type) continue;
      if (first) out << "  " << SectionName(type) << ":\n";
      first = false;
      out << "    " << YamlString(f.name) << ": {";
      if (type == Fixture::Type::kPlane) {
        out << "normal: [" << FormatExact(f.normal.x()) << ", " << FormatExact(f.normal.y()) << ", "
            << FormatExact(f.normal.z()) << "], offset: " << FormatInUnit(f.offset, L);
      } else {
        out << "xyz: [" << FormatInUnit(f.position.x(), L) << ", " << FormatInUnit(f.position.y(), L) << ", "
            << FormatInUnit(f.position.z(), L) << "]";
      }
      // A fixture that is not known keeps a prior: an sd of exactly 0 would read back as known.
      if (f.sd > 0.0) out << ", sd: " << FormatInUnit(f.sd, L);
      if (f.sd_angle > 0.0) out << ", sd_angle: " << FormatInUnit(f.sd_angle, robot.angle_unit);
      out << "}\n";
    }
  }
  return out.str();
}

}  // namespace kincal::robot_file
