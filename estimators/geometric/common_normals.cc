#include "estimators/geometric/common_normals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kincal::geometric {
namespace {

Eigen::Isometry3d Frame(const Eigen::Vector3d& origin, const Eigen::Vector3d& x, const Eigen::Vector3d& z) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d zn = z.normalized();
  const Eigen::Vector3d xn = (x - x.dot(zn) * zn).normalized();
  T.linear().col(0) = xn;
  T.linear().col(1) = zn.cross(xn);
  T.linear().col(2) = zn;
  T.translation() = origin;
  return T;
}

// A unit vector perpendicular to z, as close as possible to `hint` (any perpendicular if hint is along z).
Eigen::Vector3d PerpendicularNear(const Eigen::Vector3d& z, const Eigen::Vector3d& hint) {
  Eigen::Vector3d v = hint - hint.dot(z) * z;
  if (v.norm() < 1e-9 * std::max(1.0, hint.norm())) {
    int least = 0;
    z.cwiseAbs().minCoeff(&least);
    v = z.cross(Eigen::Vector3d::Unit(least));
  }
  return v.normalized();
}

// The parallel-axes convention (common_normals.h) for axes i (through `origin`, direction Z) and `next`:
// X_i, the line axis i+1 is held as, and the tilt dropped or kept in *pair.
AxisLine ParallelNormal(const Eigen::Vector3d& origin, const Eigen::Vector3d& Z, const AxisLine& next, double a_nominal,
                        const Eigen::Vector3d& expected, bool keep_tilt, Eigen::Vector3d* X, JointPair* pair) {
  const Eigen::Vector3d Zn = next.direction.normalized();
  // On axis i+1: where it crosses the plane through the origin perpendicular to Z_i (keep_tilt), or its
  // point nearest the origin.
  const Eigen::Vector3d nearest = keep_tilt
                                      ? Eigen::Vector3d(next.point + ((origin - next.point).dot(Z) / Zn.dot(Z)) * Zn)
                                      : Eigen::Vector3d(next.point + (origin - next.point).dot(Zn) * Zn);
  const Eigen::Vector3d v = nearest - origin;
  const Eigen::Vector3d v_perp = v - v.dot(Z) * Z;
  if (std::abs(a_nominal) > 1e-12 && v_perp.norm() > 0.0) {
    *X = (a_nominal > 0.0 ? 1.0 : -1.0) * v_perp.normalized();
  } else {
    *X = expected;  // nominally coaxial: the nominal theta decides the direction
  }
  const double tilt = std::clamp(Zn.dot(*X), -1.0, 1.0);
  if (keep_tilt) {
    pair->kept_tilt = std::asin(tilt);
    return {nearest, Zn};
  }
  pair->dropped_tilt = std::asin(tilt);
  return {origin + v.dot(*X) * *X, (Zn - tilt * *X).normalized()};
}

}  // namespace

AxisFrames FramesFromAxes(const std::vector<AxisLine>& axes, const std::vector<MdhRow>& nominal,
                          const Eigen::VectorXd& q_cal, const Eigen::Vector3d& x1_hint, double parallel_threshold,
                          bool keep_tilt) {
  const int n = static_cast<int>(axes.size());
  if (n < 1 || static_cast<int>(nominal.size()) != n || q_cal.size() != n) {
    throw std::invalid_argument("frames from axes: axes, nominal rows and joint angles differ in count");
  }
  const double sin_threshold = std::sin(std::min(parallel_threshold, M_PI / 2));
  AxisFrames out;
  out.frames.resize(n);
  out.model_axes.resize(n);
  AxisLine axis = axes[0];  // axis i as the frames hold it
  axis.direction.normalize();
  Eigen::Vector3d foot = axis.point;  // the previous normal's foot on axis i (i >= 2)
  Eigen::Vector3d x_prev = Eigen::Vector3d::Zero();

  for (int i = 1; i <= n; ++i) {
    const Eigen::Vector3d& Z = axis.direction;
    out.model_axes[i - 1] = axis;
    // The direction the nominal theta_i predicts for X_i: the fallback sign reference.
    const Eigen::Vector3d expected =
        i == 1 ? PerpendicularNear(Z, x1_hint)
               : PerpendicularNear(Z, Eigen::AngleAxisd(nominal[i - 1].theta + q_cal[i - 1], Z) * x_prev);
    if (i == n) {
      const Eigen::Vector3d origin = n == 1 ? axis.point : Eigen::Vector3d(foot + nominal[n - 1].d * Z);
      out.frames[n - 1] = Frame(origin, expected, Z);
      break;
    }
    const AxisLine& next = axes[i];
    const Eigen::Vector3d Zn = next.direction.normalized();
    const Eigen::Vector3d w = Z.cross(Zn);
    const double s = w.norm();
    JointPair pair;
    pair.joint = i;
    pair.angle = std::asin(std::min(1.0, s));
    Eigen::Vector3d origin, X;
    AxisLine held_next;
    if (s >= sin_threshold && s > 0.0) {
      // Closest points of two skew lines: origin on axis i, end on axis i+1.
      const Eigen::Vector3d d = next.point - axis.point;
      const double t = d.cross(Zn).dot(w) / (s * s);
      const double u = d.cross(Z).dot(w) / (s * s);
      origin = axis.point + t * Z;
      const Eigen::Vector3d end = next.point + u * Zn;
      const double alpha_nominal = nominal[i].alpha;
      double sign;
      if (std::abs(std::sin(alpha_nominal)) >= sin_threshold)
        sign = alpha_nominal > 0.0 ? 1.0 : -1.0;
      else
        sign = w.dot(expected) >= 0.0 ? 1.0 : -1.0;
      X = sign * w / s;
      held_next = {end, Zn};
    } else {
      pair.parallel = true;
      origin = i == 1 ? Eigen::Vector3d(axis.point + (next.point - axis.point).dot(Z) * Z)
                      : Eigen::Vector3d(foot + nominal[i - 1].d * Z);
      held_next = ParallelNormal(origin, Z, next, nominal[i].a, expected, keep_tilt, &X, &pair);
    }
    out.frames[i - 1] = Frame(origin, X, Z);
    out.pairs.push_back(pair);
    x_prev = out.frames[i - 1].linear().col(0);
    foot = held_next.point;
    axis = held_next;
  }
  return out;
}

}  // namespace kincal::geometric
