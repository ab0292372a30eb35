#pragma once
// The simulator's instruments (robot/simulator.h): what a row reads of the truth's marker. A tracker
// reads the point; a gauge some of its axes; a ballbar or a cable its distance to a pivot; a touch probe
// is on a plane when it triggers; a sphere socket holds the marker at one point. For planes and sockets
// the simulator finds configurations of the truth arm that touch them.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "framework/options.h"
#include "framework/random.h"
#include "robot/fixtures.h"
#include "robot/robot.h"

namespace kincal {

struct InstrumentOptions {
  // point: a tracker (x, y, z); partial: the axes in `axes`; distance: to pivots; plane: touch-probe
  // contacts with planes; socket: the marker held at fixed points.
  std::string instrument = "point";
  std::string axes = "z";   // partial: the axes measured, a subset of "xyz"
  // distance, plane, socket: the truth robot's fixtures of that type when it gives some (robot file
  // `fixtures:`), else this many random ones; rows are shared among them in turn.
  int fixtures = 3;
  double pivot_distance = 0.7;  // m: random pivots lie this far from the base origin
  int attempts = 200;           // plane, socket: random starts tried per contact

  static const OptionTable<InstrumentOptions>& Table();
  bool Contacts() const { return instrument == "plane" || instrument == "socket"; }
};

// The fixtures the instrument measures against (none for point and partial): the truth's own of the
// type, else random ones from `seed`: pivots at pivot_distance from the base origin, up to 30 degrees
// above its x-y plane; planes through the marker at random configurations, normals the axes of one random
// rotation (a corner's floor and walls); sockets at the marker of random configurations.
std::vector<Fixture> InstrumentFixtures(const Robot& nominal, const Robot& truth, const InstrumentOptions& options,
                                        const std::string& marker, uint64_t seed);

// Commanded angles at which the truth arm's marker touches `target` (a plane: n . p = offset; a point:
// p = position), coming from `previous_command` (null: none): a damped least-squares solve on the truth's
// actual angles from random starts within the nominal's limits, converted to the controller's commands
// (robot/joint_readings.h ReadingsFromActual); commands outside the limits are refused and the next start
// tried. Throws std::invalid_argument after `attempts` starts.
Eigen::VectorXd FindContact(const Robot& nominal, const Robot& truth, const Fixture& target, const std::string& marker,
                            const Eigen::VectorXd* previous_command, int attempts, Rng* rng);

// What the instrument reads of the true marker position, into *row: noise of sigma along what it reads
// (each measured axis; the distance's line). Plane and socket rows carry no reading (their noise is in
// the contact's target). `fixture`: the row's fixture (distance, plane, socket), else null.
void MeasureRow(const InstrumentOptions& options, const Fixture* fixture, const Eigen::Vector3d& p_true, double sigma,
                Rng* noise, Measurement* row);

}  // namespace kincal
