#pragma once
// The geometry under the closed-form inverse kinematics (robot/nominal_ik.cc): joint screws and
// their exponentials, the Paden-Kahan subproblems 1 and 2, Pieper's 3R positioning problem (with the
// roots of its polynomial), the planar elbow of three parallel axes, and where lines meet. Angles in rad,
// lengths in m; no allocation per call.
#include <cmath>
#include <complex>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kincal::ik {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// A revolute joint's screw at q = 0: unit direction w and a point p on the axis (space frame).
struct Screw {
  Vector3d w, p;
};

// A cosine and sine pair of an angle.
struct CosSin {
  double c = 1.0, s = 0.0;
  static CosSin Of(double angle) { return {std::cos(angle), std::sin(angle)}; }
  CosSin Negated() const { return {c, -s}; }
};

// The rotation about unit w by the angle of cosine c and sine s (Rodrigues, in the order of Eigen's
// AngleAxis, so that Rot(w, CosSin::Of(a)) is Eigen's to the last bit). The closed forms pass the
// cosine and sine their subproblems find, which spares a sincos per rotation.
inline Matrix3d Rot(const Vector3d& w, const CosSin& angle) {
  const double c = angle.c, s = angle.s;
  Matrix3d R;
  const Vector3d sin_axis = s * w, cos1_axis = (1.0 - c) * w;
  double t = cos1_axis.x() * w.y();
  R(0, 1) = t - sin_axis.z();
  R(1, 0) = t + sin_axis.z();
  t = cos1_axis.x() * w.z();
  R(0, 2) = t + sin_axis.y();
  R(2, 0) = t - sin_axis.y();
  t = cos1_axis.y() * w.z();
  R(1, 2) = t - sin_axis.x();
  R(2, 1) = t + sin_axis.x();
  R.diagonal() = (cos1_axis.cwiseProduct(w)).array() + c;
  return R;
}
inline Matrix3d Rot(const Vector3d& w, double angle) { return Rot(w, CosSin::Of(angle)); }

inline Isometry3d Exp(const Screw& s, const CosSin& angle) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Rot(s.w, angle);
  T.translation() = s.p - T.linear() * s.p;
  return T;
}
inline Isometry3d Exp(const Screw& s, double angle) { return Exp(s, CosSin::Of(angle)); }


// M E_s(q) M^-1 = E_{M s}(q).
inline Screw Moved(const Isometry3d& M, const Screw& s) { return {M.linear() * s.w, M * s.p}; }

// Paden-Kahan subproblem 1: the angle about w that turns x into y (their components across w).
// *degenerate when x has (almost) no such component: every angle does. *cs: the angle's cosine and
// sine, from the same components (to rounding those of the angle returned).
double Subproblem1(const Vector3d& w, const Vector3d& x, const Vector3d& y, bool* degenerate = nullptr,
                   CosSin* cs = nullptr);

// Paden-Kahan subproblem 2 for unit vectors: angles (a, b) with Rot(w1, a) Rot(w2, b) u = v; w1, w2 not
// parallel. The intermediate c = Rot(w2, b) u = Rot(w1, -a) v has known heights along w1 and w2.
// Where c lies on w1 (v on w1: a wrist whose outer axes line up), every a does and only the sum of a and
// the last turn of the chain matters; where u lies on w2, every b does. Such a free angle takes the
// given value (the reference's) and sets bit 0 (a) or 1 (b) of *free. v within 1e-7 of w1 (u of w2)
// but not within rounding: the free pair and the general ones, since the inputs may carry the error of
// a double root (sqrt(eps)) upstream; the polish on the model keeps whichever reaches the pose.
struct AnglePairs {
  int size = 0;
  std::pair<double, double> pair[3];
  int free[3] = {0, 0, 0};  // per pair, its free angles
  CosSin cs[3][2];          // per pair, the cosines and sines of its two angles
  const std::pair<double, double>* begin() const { return pair; }
  const std::pair<double, double>* end() const { return pair + size; }
};
AnglePairs Subproblem2(const Vector3d& w1, const Vector3d& w2, const Vector3d& u, const Vector3d& v, double free_a,
                       double free_b, int* free);

// A unit vector across w.
Vector3d Across(const Vector3d& w);

// The degree complex roots of the real polynomial P[0] + P[1] t + ... + P[degree] t^degree (P[degree]
// finite and not 0, else none: returns 0), by the Aberth-Ehrlich iteration (Aberth 1973: Newton's step on
// each root, corrected by the repulsion of the others; all roots at once, cubically convergent), to
// rounding. The fallback of Solve3R's eigenvalue solver where its real Schur form does not converge, in
// place of Eigen's complex eigensolver (9 s of the 17 s of CPU ik_geometry.cc took to compile at -O3, for
// a path almost never taken).
int PolynomialRoots(const double* P, int degree, std::complex<double>* roots);

// A short list of fixed capacity (no allocation per solve); Push beyond the capacity is dropped (and
// flagged); the capacities below are the most the closed forms can produce.
template <typename T, int Capacity>
struct FixedList {
  static constexpr int kCapacity = Capacity;
  int size = 0;
  bool overflow = false;
  T item[kCapacity];
  void Push(const T& x) {
    if (size < kCapacity) {
      item[size++] = x;
    } else {
      overflow = true;
    }
  }
  const T* begin() const { return item; }
  const T* end() const { return item + size; }
};

// 3R positioning: angles (a, b, c) with E_A(a) E_B(b) E_C(c) p0 = p. Pieper's invariants of the rotation
// about A, |f - pA|^2 and wA.(f - pA) for f = E_B(b) E_C(c) p0, give two equations
//     alpha_i(c) cos b + beta_i(c) sin b + gamma_i(c) = 0,   i = 1, 2,
// with alpha, beta, gamma of degree 1 in (cos c, sin c). Eliminating b (cos^2 b + sin^2 b = 1) leaves
//     F(c) = (beta1 gamma2 - beta2 gamma1)^2 + (alpha2 gamma1 - alpha1 gamma2)^2 - (alpha1 beta2 - alpha2 beta1)^2,
// a trigonometric polynomial of degree <= 4: its Fourier coefficients come exactly from 16 samples, its
// roots from TrigRoots, each polished by Newton steps on F. Where A and B meet, the first equation loses
// b and alone gives c; where they are parallel, the second does (F has only double roots in both cases,
// which an eigenvalue solver finds to sqrt(eps) at best).
// A continuum of solutions (the arm at a singular configuration that frees a joint) takes the joint's
// value from free[] and sets its bit in *free_mask (1: a, 2: b, 4: c): c where F (or the equation in c
// alone) vanishes identically, b where E_C(c) p0 lies on B (both equations lose b), a where
// E_B(b) E_C(c) p0 lies on A.
// rotations (optional): per position, R_A(a) R_B(b) R_C(c), the rotation of the chain.
using Positions = FixedList<Vector3d, 16>;
Positions Solve3R(Screw A, Screw B, const Screw& C, const Vector3d& p0, const Vector3d& p, const double free[3],
                  int* free_mask, FixedList<Matrix3d, 16>* rotations = nullptr);

// The planar triple of three parallel axes P1, P2, P3 (direction w; robot/nominal_ik.cc's parallel
// closed form): an elbow that takes the point of axis P3 (at distance r2 from axis P2) to a point at
// distance r1 from axis P1, reachable for |dist - r2| <= r1 <= dist + r2 (dist: between axes P1 and P2).
struct PlanarElbow {
  Vector3d w, c1, c2, dv;
  double dist, r2;

  PlanarElbow(const Screw& P1, const Screw& P2, const Screw& P3)
      : w(P1.w), c1(Flat(P1.p)), c2(Flat(P2.p)), dv(c2 - c1), dist(dv.norm()), r2(Flat(P3.p - P2.p).norm()) {}
  Vector3d Flat(const Vector3d& x) const { return Vector3d(x - w * w.dot(x)); }

  // Where the wrist is singular, the free angle x of screw S moves that point on the circle
  // t(x) = Q E_S(-x) g, in a plane across w: |flat(t) - c1|^2 = K + alpha cos x + beta sin x. The angle
  // closest to `reference` that keeps it within reach (the reference itself, else an edge of the arc).
  double ReachableFreeAngle(const Isometry3d& Q, const Screw& S, const Vector3d& g, double reference) const;
};

// The lone joint X of three parallel axes (direction w) whose pair meets at `center`: the planar triple
// keeps heights along w, w.(E_X(-a) M u - u) = 0, with E_Y, E_Z fixing u. <= 2 angles into as; a shoulder
// singularity (the pair's point on axis X, the same height for every a) gives `free_a` and sets bit 0.
int ShoulderAngles(const Screw& X, const Vector3d& w, const Isometry3d& M, const Vector3d& center, double free_a,
                   double* as, int* free_mask);

// The point where three lines meet (least squares) and the largest distance of it to them.
Vector3d CommonPoint(const Screw* s, int count, double* distance);

// The distance between two lines (parallel ones: between any two of their points across).
double LineDistance(const Screw& a, const Screw& b);

}  // namespace kincal::ik
