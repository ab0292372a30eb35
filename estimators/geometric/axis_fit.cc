#include "estimators/geometric/axis_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "estimators/geometric/stop_angles.h"

namespace kincal::geometric {
namespace {

// Two unit vectors perpendicular to a (unit) and to each other.
void Perpendiculars(const Eigen::Vector3d& a, Eigen::Vector3d* b1, Eigen::Vector3d* b2) {
  const Eigen::Vector3d helper = std::abs(a.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  *b1 = (helper - helper.dot(a) * a).normalized();
  *b2 = a.cross(*b1);
}

struct Line {
  Eigen::Vector3d point, direction;
  std::vector<double> radius, height;  // per marker; height of its circle's centre along the line from point
};

// Residuals: per marker, per stop, (axial, radial).
Eigen::VectorXd Residuals(const std::vector<std::vector<Eigen::Vector3d>>& points, const Line& line) {
  const int M = static_cast<int>(points.size()), m = static_cast<int>(points[0].size());
  Eigen::VectorXd r(2 * M * m);
  for (int i = 0; i < M; ++i) {
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector3d d = points[i][k] - line.point;
      const double along = d.dot(line.direction);
      r[2 * (i * m + k)] = along - line.height[i];
      r[2 * (i * m + k) + 1] = (d - along * line.direction).norm() - line.radius[i];
    }
  }
  return r;
}

// Jacobian with respect to (v1, v2, u1, u2, radius_1..M, height_1..M): point += v1 b1 + v2 b2, direction
// = normalise(direction + u1 b1 + u2 b2).
Eigen::MatrixXd Jacobian(const std::vector<std::vector<Eigen::Vector3d>>& points, const Line& line,
                         const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const int M = static_cast<int>(points.size()), m = static_cast<int>(points[0].size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * M * m, 4 + 2 * M);
  const Eigen::Vector3d& a = line.direction;
  for (int i = 0; i < M; ++i) {
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector3d d = points[i][k] - line.point;
      const double along = d.dot(a);
      const Eigen::Vector3d w = d - along * a;
      const double rho = w.norm();
      const Eigen::Vector3d w_hat = rho > 0.0 ? Eigen::Vector3d(w / rho) : Eigen::Vector3d::Zero();
      const int row = 2 * (i * m + k);
      // axial = d.a - h: d/dpoint = -a, d/ddirection = d.
      J(row, 0) = -a.dot(b1);
      J(row, 1) = -a.dot(b2);
      J(row, 2) = d.dot(b1);
      J(row, 3) = d.dot(b2);
      J(row, 4 + M + i) = -1.0;
      // radial = |d - (d.a) a| - R: d/dpoint = -w_hat (w is perpendicular to a), d/ddirection = -(d.a) w_hat.
      J(row + 1, 0) = -w_hat.dot(b1);
      J(row + 1, 1) = -w_hat.dot(b2);
      J(row + 1, 2) = -along * w_hat.dot(b1);
      J(row + 1, 3) = -along * w_hat.dot(b2);
      J(row + 1, 4 + i) = -1.0;
    }
  }
  return J;
}

Line Step(const Line& line, const Eigen::VectorXd& delta, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const int M = static_cast<int>(line.radius.size());
  Line next = line;
  next.point = line.point + delta[0] * b1 + delta[1] * b2;
  next.direction = (line.direction + delta[2] * b1 + delta[3] * b2).normalized();
  for (int i = 0; i < M; ++i) {
    next.radius[i] += delta[4 + i];
    next.height[i] += delta[4 + M + i];
  }
  return next;
}

// Start: each marker alone (into *alone), axes brought to one sign, weighted by radius^2 (how well an
// arc shows its axis' direction grows with its radius); the line through the mean of the circles' centres.
Line StartLine(const std::vector<std::vector<Eigen::Vector3d>>& points, const std::vector<double>& x,
               const ArcFitOptions& options, std::vector<ArcFit>* alone) {
  const int M = static_cast<int>(points.size()), m = static_cast<int>(x.size());
  for (int i = 0; i < M; ++i) {
    if (static_cast<int>(points[i].size()) != m) throw std::logic_error("axis fit: every marker needs every stop");
    try {
      alone->push_back(FitArc(points[i], x, options));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("marker " + std::to_string(i + 1) + " of " + std::to_string(M) + ": " + e.what());
    }
  }
  Eigen::Vector3d direction = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
  for (const ArcFit& f : *alone) {
    const double sign = f.axis.dot((*alone)[0].axis) < 0.0 ? -1.0 : 1.0;
    direction += sign * f.radius * f.radius * f.axis;
    centre += f.center / M;
  }
  Line line;
  line.direction = direction.normalized();
  line.point = centre;
  for (const ArcFit& f : *alone) {
    line.radius.push_back(f.radius);
    line.height.push_back((f.center - centre).dot(line.direction));
  }
  return line;
}

// Refine: Levenberg-Marquardt, to rounding level. *r: the residuals of the line returned.
Line Refine(const std::vector<std::vector<Eigen::Vector3d>>& points, Line line, int max_iterations, Eigen::VectorXd* r,
            int* iterations, bool* converged) {
  const int M = static_cast<int>(points.size());
  *r = Residuals(points, line);
  double cost = r->squaredNorm();
  double lambda = 1e-9;
  *iterations = 0;
  *converged = false;
  while (*iterations < max_iterations && !*converged) {
    ++*iterations;
    Eigen::Vector3d b1, b2;
    Perpendiculars(line.direction, &b1, &b2);
    const Eigen::MatrixXd J = Jacobian(points, line, b1, b2);
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * *r;
    bool accepted = false;
    for (int tries = 0; tries < 30 && !accepted; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * JtJ.diagonal().cwiseMax(1e-30);
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      const Line next = Step(line, delta, b1, b2);
      const Eigen::VectorXd r_next = Residuals(points, next);
      const double cost_next = r_next.squaredNorm();
      if (cost_next <= cost) {
        accepted = true;
        // At rounding level: the step no longer changes the line (relative to its size).
        const double scale = 1.0 + line.point.norm();
        *converged = delta.head<2>().norm() < 1e-15 * scale && delta.segment<2>(2).norm() < 1e-15 &&
                     delta.tail(2 * M).lpNorm<Eigen::Infinity>() < 1e-15 * scale;
        *converged = *converged || cost - cost_next <= 1e-28 * (1.0 + cost);
        line = next;
        *r = r_next;
        cost = cost_next;
        lambda = std::max(lambda / 10.0, 1e-15);
      } else {
        lambda *= 10.0;
      }
    }
    if (!accepted) *converged = true;  // no step lowers the cost: at the minimum to rounding
  }
  return line;
}

// Angles about the common axis, one in-plane frame (fit->e1, e2) for every marker, signed and unwrapped
// (the axis and heights turned over where the markers turn the other way), and their line in x.
AngleLine FitAngles(const std::vector<std::vector<Eigen::Vector3d>>& points, const std::vector<double>& x,
                    const Eigen::Vector3d& e1_start, Line* line, ArcFit* fit,
                    std::vector<std::vector<double>>* angles) {
  const int M = static_cast<int>(points.size()), m = static_cast<int>(x.size());
  Eigen::Vector3d e1 = e1_start - e1_start.dot(line->direction) * line->direction;
  if (e1.norm() < 1e-6) Perpendiculars(line->direction, &e1, &fit->e2);
  fit->e1 = e1.normalized();
  fit->e2 = line->direction.cross(fit->e1);
  fit->axis = line->direction;
  std::vector<std::vector<double>> raw(M, std::vector<double>(m));
  std::vector<double> weights(M);
  for (int i = 0; i < M; ++i) {
    weights[i] = line->radius[i] * line->radius[i];
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector3d d = points[i][k] - line->point;
      raw[i][k] = std::atan2(d.dot(fit->e2), d.dot(fit->e1));
    }
  }
  if (SignAndUnwrap(raw, x, weights, angles) < 0) {
    fit->axis = -fit->axis;
    fit->e2 = -fit->e2;
    for (double& h : line->height) h = -h;
  }
  const AngleLine angle_line = FitAngleLine(*angles, x, weights);
  if (!(angle_line.slope > 0.0) || !std::isfinite(angle_line.slope)) {
    throw std::invalid_argument("the markers do not turn about the fitted axis with the joint's angle");
  }
  return angle_line;
}

}  // namespace

ArcFit FitAxis(const std::vector<std::vector<Eigen::Vector3d>>& points, const std::vector<double>& x,
               const ArcFitOptions& options) {
  const int M = static_cast<int>(points.size());
  if (M == 0) throw std::invalid_argument("axis fit: no markers");
  if (M == 1) return FitArc(points[0], x, options);
  const int m = static_cast<int>(x.size());
  std::vector<ArcFit> alone;
  Line line = StartLine(points, x, options, &alone);
  Eigen::VectorXd r;
  int iterations = 0;
  bool converged = false;
  line = Refine(points, line, options.max_iterations, &r, &iterations, &converged);

  ArcFit fit;
  std::vector<std::vector<double>> angles;
  const AngleLine angle_line = FitAngles(points, x, alone[0].e1, &line, &fit, &angles);
  fit.angle_slope = angle_line.slope;

  double axial2 = 0.0, radial2 = 0.0, tangential2 = 0.0;
  for (int i = 0; i < M; ++i) {
    MarkerCircle c;
    c.center = line.point + line.height[i] * fit.axis;
    c.radius = line.radius[i];
    c.angle_intercept = angle_line.intercepts[i];
    c.angles = angles[i];
    for (int k = 0; k < m; ++k) {
      axial2 += std::pow(r[2 * (i * m + k)], 2);
      radial2 += std::pow(r[2 * (i * m + k) + 1], 2);
      tangential2 += std::pow(c.radius * (c.angles[k] - c.angle_intercept - fit.angle_slope * x[k]), 2);
    }
    fit.circles.push_back(c);
  }
  const MarkerCircle& first = fit.circles[0];
  fit.center = first.center;
  fit.radius = first.radius;
  fit.angle_intercept = first.angle_intercept;
  fit.angles = first.angles;
  const auto [phi_min, phi_max] = std::minmax_element(fit.angles.begin(), fit.angles.end());
  fit.arc = *phi_max - *phi_min;
  fit.stops = m;
  const double count = static_cast<double>(M * m);
  fit.axial_rms = std::sqrt(axial2 / count);
  fit.radial_rms = std::sqrt(radial2 / count);
  fit.tangential_rms = std::sqrt(tangential2 / count);
  fit.residual_sum_squares = axial2 + radial2 + tangential2;
  // 3 coordinates per point; the line 4, a radius, height and phase per marker, one slope.
  fit.degrees_of_freedom = 3 * M * m - 3 * M - 5;
  fit.iterations = iterations;
  for (const ArcFit& f : alone) fit.iterations += f.iterations;
  fit.converged = converged;
  return fit;
}

}  // namespace kincal::geometric
