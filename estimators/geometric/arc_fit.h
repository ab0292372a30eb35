#pragma once
// A joint's axis from the arc its marker traces (METHOD.md 2, steps 1-4), and the angle of each stop
// about that axis (METHOD.md 3.1).
//
// The stops of one sweep are fitted with a total-least-squares plane and, in that plane, a circle; the
// circle's centre is a point of the axis and the plane's normal its direction. The normal is signed by
// the direction of rotation: the in-plane angle of the stops must grow with the joint's drive variable x
// (the joint angle the start robot's drives give the encoder counts; see sweeps.h), which is the
// right-hand rule about the axis. The steps of x between stops (sorted) decide the sign and unwrap the
// angles (stop_angles.h: wrist sweeps can turn more than pi between stops); beyond that the scale of x
// enters only the angle regression phi = intercept + slope * x, whose slope is K_start / K_actual
// (METHOD.md 3).
//
// The paper measures each stop's angle from the first stop (METHOD.md 3.1); here every stop's angle is
// measured from the fixed in-plane direction e1, so that the first stop's noise is not shared by every
// angle. The regression slope is the same.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimators/geometric/circle_fit.h"
#include "framework/options.h"

namespace kincal::geometric {

struct ArcFitOptions {
  // Circle fit in the plane of the arc. Default: the orthogonal-distance fit, the most accurate on the
  // seed's short arcs (tests/estimators/geometric/circle_fit_test.cc, bench/geometric_accuracy.cc).
  CircleFitMethod circle_fit = CircleFitMethod::kGeometric;
  // Smallest RMS spread of the stops about their centroid, m: below it the marker did not move (it sits
  // on the axis, or the joint did not turn). 1 um is below any tracker's resolution.
  double min_spread = 1e-6;
  // The stops' RMS deviation from their best straight line (in the plane) must exceed this multiple of
  // their RMS distance from the plane (the noise): below it the arc's curvature, and so its centre, is
  // not determined by the data (for 20 stops of pure noise the ratio is rarely above 2; the seed's
  // 40 deg arcs pass up to about 0.4 mm of noise). 0 keeps only the check for exactly collinear stops.
  double min_curvature_ratio = 2.0;
  // Iteration limit of the geometric circle fit.
  int max_iterations = 100;

  // Keys circle_fit, min_spread (a length), min_curvature_ratio, max_iterations.
  static const OptionTable<ArcFitOptions>& Table();
  bool IsValid(std::string* why) const;
};

// One marker's circle about a joint's axis (several markers on one link share the axis and the slope).
struct MarkerCircle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // on the axis, m
  double radius = 0.0;                               // m
  double angle_intercept = 0.0;                      // its angle about the axis, from e1, at x = 0
  std::vector<double> angles;                        // each stop's angle (unwrapped), input order
};

struct ArcFit {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // circle centre: a point of the axis, m
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // unit; the joint turns positively about it
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();     // in-plane unit vectors, e1 x e2 = axis
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  double radius = 0.0;  // m
  // In-plane angle of the marker about the axis, from e1, as a function of the drive variable x.
  double angle_intercept = 0.0;
  double angle_slope = 1.0;    // K_start / K_actual
  std::vector<double> angles;  // each stop's angle (unwrapped), input order
  double arc = 0.0;            // angle between the extreme stops, rad
  int stops = 0;
  // RMS residuals of the stops: distance from the plane, from the circle in the plane, and along the
  // circle from the angle regression (radius x angle residual), m.
  double axial_rms = 0.0, radial_rms = 0.0, tangential_rms = 0.0;
  double residual_sum_squares = 0.0;  // of all three components, m^2
  // 3 stops - 8 (plane 3, circle 3, regression 2); FitAxis, M markers: 3 M stops - 3 M - 5.
  int degrees_of_freedom = 0;
  int iterations = 0;
  bool converged = true;

  // Every marker's circle (FitArc: one, equal to the fields above; FitAxis: one per marker, and the
  // fields above are the first marker's).
  std::vector<MarkerCircle> circles;

  double AngleAt(double x) const { return angle_intercept + angle_slope * x; }
  Eigen::Vector3d PointAtAngle(double phi) const;
  // Marker `marker` (index into circles) where the joint's drive variable is x.
  Eigen::Vector3d MarkerAt(int marker, double x) const;
};

// `x`: the joint's drive variable at each stop (any order); it signs the axis and unwraps the angles
// (stop_angles.h), so stops may be more than pi apart. Throws std::invalid_argument, without
// context (the caller names the sweep), for fewer than 3 stops, a joint that does not move, coincident
// or collinear stops.
ArcFit FitArc(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& x, const ArcFitOptions& options);

}  // namespace kincal::geometric
