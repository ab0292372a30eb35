#pragma once
// Total-least-squares plane through 3-D points (METHOD.md 2, step 2). The paper fits z = a + b x + c y in
// a temporary frame; the orthogonal (total least squares) fit is the better-conditioned equivalent: it
// minimises the sum of squared distances to the plane whatever the plane's orientation. The centred
// points' singular value decomposition gives the plane (the smallest singular direction is the normal)
// and, in the two larger singular values, how far the points spread along and across their main line,
// which the arc fit uses to refuse coincident or collinear stops.
#include <vector>

#include <Eigen/Core>

namespace kincal::geometric {

struct PlaneFit {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit; its sign is arbitrary
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();      // in-plane unit vectors, e1 x e2 = normal
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  // RMS spread of the centred points along e1, e2 and the normal (singular values / sqrt(count)), m.
  // spread[2] is the RMS distance of the points from the plane.
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
};

// Needs at least one point; with fewer than three the normal is not determined (spread[1] is 0).
PlaneFit FitPlane(const std::vector<Eigen::Vector3d>& points);

}  // namespace kincal::geometric
