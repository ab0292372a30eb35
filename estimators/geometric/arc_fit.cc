#include "estimators/geometric/arc_fit.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "estimators/geometric/plane_fit.h"
#include "estimators/geometric/stop_angles.h"

namespace kincal::geometric {
namespace {

std::string Mm(double metres) {
  std::ostringstream s;
  s.precision(3);
  s << metres * 1e3 << " mm";
  return s.str();
}

}  // namespace

const OptionTable<ArcFitOptions>& ArcFitOptions::Table() {
  using A = ArcFitOptions;
  static const OptionTable<A> table =
      OptionTable<A>("arc fit")
          .Add<std::string>(
              "circle_fit", [](const A& a) { return ToString(a.circle_fit); },
              [](A* a, const std::string& name) { a->circle_fit = ParseCircleFitMethod(name); },
              "circle fit: geometric, taubin, pratt or kasa")
          .Add("min_spread", OptionUnit::kLength, &A::min_spread, "smallest RMS spread of an arc's stops",
               NonNegative())
          .Add("min_curvature_ratio", &A::min_curvature_ratio,
               "an arc's deviation from a line over its noise must exceed this", NonNegative())
          .Add("max_iterations", &A::max_iterations, "iteration limit of the geometric circle fit", AtLeast(1));
  return table;
}

bool ArcFitOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

Eigen::Vector3d ArcFit::PointAtAngle(double phi) const {
  return center + radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

Eigen::Vector3d ArcFit::MarkerAt(int marker, double x) const {
  const MarkerCircle& c = circles.at(marker);
  const double phi = c.angle_intercept + angle_slope * x;
  return c.center + c.radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

ArcFit FitArc(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& x, const ArcFitOptions& options) {
  const int m = static_cast<int>(points.size());
  if (static_cast<int>(x.size()) != m) throw std::invalid_argument("arc fit: points and drive values differ in count");
  if (m < 3) throw std::invalid_argument("needs at least 3 stops, got " + std::to_string(m));
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  if (!(*x_max > *x_min)) throw std::invalid_argument("the joint does not move (every stop has the same joint angle)");

  const PlaneFit plane = FitPlane(points);
  if (!(plane.spread[0] > options.min_spread)) {
    throw std::invalid_argument("the marker barely moves (RMS spread " + Mm(plane.spread[0]) + ", min_spread " +
                                Mm(options.min_spread) + "): the marker is on the joint's axis, or the stops coincide");
  }
  if (!(plane.spread[1] > std::max(options.min_curvature_ratio * plane.spread[2], 1e-9 * plane.spread[0]))) {
    throw std::invalid_argument("the stops lie on a straight line: their RMS deviation from a line, " +
                                Mm(plane.spread[1]) + ", is not above " + std::to_string(options.min_curvature_ratio) +
                                " x their RMS distance from a plane, " + Mm(plane.spread[2]) +
                                " (min_curvature_ratio), so the arc's centre is not determined");
  }

  std::vector<Eigen::Vector2d> uv(m);
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d d = points[k] - plane.centroid;
    uv[k] = Eigen::Vector2d(d.dot(plane.e1), d.dot(plane.e2));
  }
  const CircleFit2d circle = FitCircle(uv, options.circle_fit, options.max_iterations);

  ArcFit fit;
  fit.stops = m;
  fit.radius = circle.radius;
  fit.iterations = circle.iterations;
  fit.converged = circle.converged;
  fit.center = plane.centroid + circle.center.x() * plane.e1 + circle.center.y() * plane.e2;
  fit.axis = plane.normal;
  fit.e1 = plane.e1;
  fit.e2 = plane.e2;

  // Angles about the (not yet signed) normal; the sign and the unwrapping come from the drive variable.
  std::vector<double> raw(m);
  for (int k = 0; k < m; ++k) raw[k] = std::atan2(uv[k].y() - circle.center.y(), uv[k].x() - circle.center.x());
  if (SignAndUnwrap({raw}, x, {1.0}, &fit.angles) < 0) {
    // The joint turns clockwise about the SVD's normal: flip the axis (and e2, so e1 x e2 = axis).
    fit.axis = -fit.axis;
    fit.e2 = -fit.e2;
  }
  const AngleLine line = FitAngleLine({fit.angles}, x, {1.0});
  if (!(line.slope > 0.0) || !std::isfinite(line.slope)) {
    throw std::invalid_argument("the marker does not turn about the fitted axis with the joint's angle");
  }
  fit.angle_slope = line.slope;
  fit.angle_intercept = line.intercepts[0];
  const auto [phi_min, phi_max] = std::minmax_element(fit.angles.begin(), fit.angles.end());
  fit.arc = *phi_max - *phi_min;

  double axial2 = 0.0, radial2 = 0.0, tangential2 = 0.0;
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d d = points[k] - fit.center;
    const double axial = d.dot(fit.axis);
    const double radial = (d - axial * fit.axis).norm() - fit.radius;
    const double tangential = fit.radius * (fit.angles[k] - fit.AngleAt(x[k]));
    axial2 += axial * axial;
    radial2 += radial * radial;
    tangential2 += tangential * tangential;
  }
  fit.axial_rms = std::sqrt(axial2 / m);
  fit.radial_rms = std::sqrt(radial2 / m);
  fit.tangential_rms = std::sqrt(tangential2 / m);
  fit.residual_sum_squares = axial2 + radial2 + tangential2;
  fit.degrees_of_freedom = 3 * m - 8;
  fit.circles = {{fit.center, fit.radius, fit.angle_intercept, fit.angles}};
  return fit;
}

}  // namespace kincal::geometric
