#include "robot/fixtures.h"

#include <cmath>
#include <set>
#include <stdexcept>

namespace kincal {

std::string FixtureTypeName(Fixture::Type type) {
  switch (type) {
    case Fixture::Type::kPivot:
      return "pivot";
    case Fixture::Type::kPlane:
      return "plane";
    case Fixture::Type::kPoint:
      return "point";
  }
  return "pivot";
}

Fixture::Type FixtureTypeOf(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::kDistance:
      return Fixture::Type::kPivot;
    case MeasurementKind::kPlane:
      return Fixture::Type::kPlane;
    case MeasurementKind::kFixedPoint:
      return Fixture::Type::kPoint;
    case MeasurementKind::kPoint:
      break;
  }
  throw std::invalid_argument("a point row names no fixture");
}

const Fixture* Fixtures::Find(Fixture::Type type, const std::string& name) const {
  for (const Fixture& f : items)
    if (f.type == type && f.name == name) return &f;
  return nullptr;
}

Fixture* Fixtures::Find(Fixture::Type type, const std::string& name) {
  for (Fixture& f : items)
    if (f.type == type && f.name == name) return &f;
  return nullptr;
}

void Fixtures::Validate() const {
  std::set<std::pair<Fixture::Type, std::string>> seen;
  for (const Fixture& f : items) {
    const std::string what = "fixtures: " + FixtureTypeName(f.type) + " '" + f.name + "': ";
    if (f.name.empty()) throw std::invalid_argument("fixtures: a " + FixtureTypeName(f.type) + " without a name");
    if (!seen.insert({f.type, f.name}).second) throw std::invalid_argument(what + "given twice");
    if (!f.position.allFinite() || !std::isfinite(f.offset)) throw std::invalid_argument(what + "non-finite value");
    if (!(std::isfinite(f.sd) && f.sd >= 0.0) || !(std::isfinite(f.sd_angle) && f.sd_angle >= 0.0)) {
      throw std::invalid_argument(what + "expected sd and sd_angle finite and >= 0");
    }
    if (f.type == Fixture::Type::kPlane && !(f.normal.allFinite() && std::abs(f.normal.norm() - 1.0) <= 1e-6)) {
      throw std::invalid_argument(what + "expected a unit normal");
    }
  }
}

}  // namespace kincal
