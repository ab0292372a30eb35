#pragma once
// Closed-form starts of the fixtures (robot/fixtures.h) from marker positions: the start arm's predicted
// positions of the rows that name a fixture. A calibration starts an unknown fixture from these.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "robot/fixtures.h"
#include "robot/robot.h"

namespace kincal {

// The centre c of a sphere through marker positions p_i at distances d_i (a pivot): the linear solution of
// |p_i - c|^2 = d_i^2 (differences of the equations, least squares), then Gauss-Newton on
// sum (|p_i - c| - d_i)^2. Positions on one plane leave the side of the plane open: both mirror centres
// are refined and the one of smaller cost returned (ties: the one nearer `hint` when given). Needs four
// positions not on one line; throws std::invalid_argument otherwise.
Eigen::Vector3d FitSphereCentre(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& distances,
                                const Eigen::Vector3d* hint = nullptr);

// The least-squares plane of positions (three at least, not on one line): the unit normal is the
// direction of least spread (SVD of the centred positions), offset = n . centroid; the normal is turned
// so that the offset is >= 0 (for a plane through the origin: its largest component positive).
struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
};
PlaneFit FitPlane(const std::vector<Eigen::Vector3d>& points);

// The mean of the positions (one at least).
Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points);

// The robot's fixtures with every fixture the data names but the robot does not give added, unknown
// (known = false, no prior), at its closed-form start from `start`'s predicted marker positions (in the
// frame of session 0; the controller turns commanded angles into readings as in robot/prediction.h).
// Throws std::invalid_argument ("source:line: ...") when the rows of a fixture cannot fix it.
Fixtures StartFixtures(const Robot& controller, const Robot& start, const Dataset& data);

}  // namespace kincal
