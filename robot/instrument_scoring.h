#pragma once
// Comparing instruments on tracker data: tracker points turned into what another instrument would have
// read, and a score that needs no common frame. An arm calibrated from distances cannot see its base (a
// distance is the same in every frame), so it is scored by the distances between points it predicts.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "robot/prediction.h"
#include "robot/robot.h"

namespace kincal {

// The rows of `points` (every one a full point) as distances to `pivots` (m, measurement frame), row i
// to pivot i mod k, named `names[i mod k]`; every other column kept. Throws std::invalid_argument for a
// row that is not a full point, no pivots, or names and pivots of different counts.
Dataset DistancesFromPoints(const Dataset& points, const std::vector<Eigen::Vector3d>& pivots,
                            const std::vector<std::string>& names);

// Errors of `model` in the distances between the points of `points` (full points): for every pair of rows
// i < j, |(p_i - p_j)| predicted minus measured, m. Invariant to the model's base and the measurement
// frame. Throws std::invalid_argument for a row that is not a full point.
ErrorStats PairwiseDistanceErrors(const Robot& controller, const Robot& model, const Dataset& points);

}  // namespace kincal
