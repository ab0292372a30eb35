#pragma once
// One joint's axis from the arcs of several markers on the same link (several reflectors on the tool,
// measured at every stop): one line for all of them, with one radius and one height along the axis per
// marker, and one angle slope (they turn as one body) with one phase per marker.
//
// Why jointly: the markers see the same axis, and a marker close to the axis (a reflector 1.7 mm from the
// wrist's roll axis) fixes its position well but its direction hardly at all, while a far one does the
// opposite; fitted together every marker contributes what it can. Fitted apart, the tool side of the
// model would have to choose one marker (and lose the others' information), or average axes that differ
// by their noise.
//
// Method: each marker's arc is fitted alone (arc_fit.h) for a start; the line (4 parameters), radii and
// heights are then refined by Gauss-Newton with Levenberg-Marquardt damping on the orthogonal residuals
// of every stop of every marker (distance from its circle's plane, and from its circle in that plane),
// the maximum-likelihood fit for isotropic noise, iterated to rounding level so that the result is a
// smooth function of the points (uncertainty.h differentiates it). The angles about the common axis are
// then signed and unwrapped with the drive variable (stop_angles.h), and one slope and a phase per marker
// fitted with weights radius^2 (the tangential noise is the same for every marker; the angle noise is
// not). For one marker this is FitArc exactly.
#include <vector>

#include <Eigen/Core>

#include "estimators/geometric/arc_fit.h"

namespace kincal::geometric {

// `points[m][k]`: marker m at stop k (every marker measured at every stop); `x[k]`: the joint's drive
// variable. Throws std::invalid_argument (naming the marker by its index, from 1, when there are several)
// for what FitArc refuses.
ArcFit FitAxis(const std::vector<std::vector<Eigen::Vector3d>>& points, const std::vector<double>& x,
               const ArcFitOptions& options);

}  // namespace kincal::geometric
