#pragma once
// Fixtures: the fixed things other instruments measure against. A pivot is the fixed end of a distance
// (a ballbar's or a cable's), a plane is touched by a probe ball, a point is a sphere socket the marker
// returns to. The dataset's rows name them (framework/dataset.h: pivot, plane, point columns); the robot
// file's `fixtures:` section gives what is known of them (robot/robot_file.h).
//
// A fixture given with an sd is a start value with a Gaussian prior; given without any sd it is known and
// held; a fixture the data names but the robot does not is unknown: free, started from a closed form
// (robot/fixture_fits.h).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"

namespace kincal {

struct Fixture {
  enum class Type { kPivot, kPlane, kPoint };
  Type type = Type::kPivot;
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // pivot, point: m, measurement frame (session 0)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   // plane: unit normal
  double offset = 0.0;                                  // plane: n . p = offset, m
  double sd = 0.0;        // prior sd of the position (pivot, point) or the offset (plane), m; 0: none
  double sd_angle = 0.0;  // plane: prior sd of the normal's direction, rad; 0: none
  bool known = false;     // given without any sd: known exactly, held at its value
};

// "pivot", "plane" or "point".
std::string FixtureTypeName(Fixture::Type type);
// The fixture type a measurement kind names (kDistance: pivot, kPlane: plane, kFixedPoint: point);
// throws std::invalid_argument for kPoint, which names none.
Fixture::Type FixtureTypeOf(MeasurementKind kind);

struct Fixtures {
  std::vector<Fixture> items;
  // Null when absent.
  const Fixture* Find(Fixture::Type type, const std::string& name) const;
  Fixture* Find(Fixture::Type type, const std::string& name);
  bool empty() const { return items.empty(); }
  // Throws std::invalid_argument ("fixtures: what") for a duplicate name within a type, an empty name,
  // a non-unit or non-finite normal, or a negative or non-finite value.
  void Validate() const;
};

}  // namespace kincal
