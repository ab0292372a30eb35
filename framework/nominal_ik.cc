#include "framework/nominal_ik.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "framework/math.h"
#include "framework/random.h"

namespace kincal {

std::string ToString(IkStatus status) {
  switch (status) {
    case IkStatus::kSolved: return "solved";
    case IkStatus::kOutOfLimits: return "out_of_limits";
    case IkStatus::kUnreachable: return "unreachable";
    case IkStatus::kSingular: return "singular";
  }
  return "unknown";
}

bool NominalIkOptions::IsValid(std::string* why) const {
  const auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (!(position_tolerance > 0) || !(orientation_tolerance > 0)) return fail("tolerances must be > 0");
  if (!(distance_tolerance > 0) || !(direction_tolerance > 0)) return fail("detection tolerances must be > 0");
  if (!(singular_ratio >= 0 && singular_ratio < 1)) return fail("singular_ratio must be in [0, 1)");
  if (!configuration.empty()) {
    for (int s : configuration) {
      if (s < -1 || s > 1) return fail("configuration entries must be -1, 0 or +1");
    }
  }
  return numeric.IsValid(why);
}

namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

// A revolute joint's screw at q = 0: unit direction w and a point p on the axis (space frame).
struct Screw {
  Vector3d w, p;
};

Matrix3d Rot(const Vector3d& w, double angle) { return Eigen::AngleAxisd(angle, w).toRotationMatrix(); }

Isometry3d Exp(const Screw& s, double angle) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Rot(s.w, angle);
  T.translation() = s.p - T.linear() * s.p;
  return T;
}

// M E_s(q) M^-1 = E_{M s}(q).
Screw Moved(const Isometry3d& M, const Screw& s) { return {M.linear() * s.w, M * s.p}; }

// Paden-Kahan subproblem 1: the angle about w that turns x into y (their components across w).
// *degenerate when x has (almost) no such component: every angle does.
double Subproblem1(const Vector3d& w, const Vector3d& x, const Vector3d& y, bool* degenerate = nullptr) {
  const Vector3d xp = x - w * w.dot(x), yp = y - w * w.dot(y);
  if (degenerate) *degenerate = xp.norm() < 1e-12 * (1.0 + x.norm());
  return std::atan2(w.dot(xp.cross(yp)), xp.dot(yp));
}

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
  const std::pair<double, double>* begin() const { return pair; }
  const std::pair<double, double>* end() const { return pair + size; }
};
AnglePairs Subproblem2(const Vector3d& w1, const Vector3d& w2, const Vector3d& u, const Vector3d& v, double free_a,
                       double free_b, int* free) {
  AnglePairs out;
  const double k = w1.dot(w2);
  const Vector3d n = w1.cross(w2);
  const double n2 = n.squaredNorm();
  if (n2 < 1e-20) return out;
  // The free cases first: there c's component across w1 (or w2) is rounding, and the angle it gives
  // arbitrary.
  const double across_v = (v - w1 * w1.dot(v)).norm(), across_u = (u - w2 * w2.dot(u)).norm();
  if (across_v < 1e-7) {
    *free |= 1;
    out.free[out.size] = 1;
    out.pair[out.size++] = {free_a, Subproblem1(w2, u, v)};
    if (across_v < 1e-12) return out;
  } else if (across_u < 1e-7) {
    *free |= 2;
    out.free[out.size] = 2;
    out.pair[out.size++] = {Subproblem1(w1, u, v), free_b};
    if (across_u < 1e-12) return out;
  }
  const double h1 = w1.dot(v), h2 = w2.dot(u);  // the heights of c
  const double alpha = (h1 - k * h2) / (1 - k * k);
  const double beta = (h2 - k * h1) / (1 - k * k);
  // c = alpha w1 + beta w2 + g n with g^2 n2 = |c|^2 - |alpha w1 + beta w2|^2. Written as that difference it
  // loses all accuracy next to the free cases (both terms 1, the difference eps^2 for v eps off w1);
  // with |c| = |v| split into its part along n and its heights, (w1.v, w2.v), the difference is
  //     g^2 n2^2 = (v.n)^2 + (w2.v - h2) (w2.v + h2 - 2 k h1)
  // (or the same with u, w2 and w1, h1 exchanged), products of small terms each accurate to rounding.
  const double g2 = across_v <= across_u
                        ? (std::pow(v.dot(n), 2) + (w2.dot(v) - h2) * (w2.dot(v) + h2 - 2 * k * h1)) / (n2 * n2)
                        : (std::pow(u.dot(n), 2) + (w1.dot(u) - h1) * (w1.dot(u) + h1 - 2 * k * h2)) / (n2 * n2);
  if (g2 < -1e-8) return out;
  for (double sign : {1.0, -1.0}) {
    const Vector3d c = alpha * w1 + beta * w2 + sign * std::sqrt(std::max(g2, 0.0)) * n;
    out.pair[out.size++] = {Subproblem1(w1, c, v), Subproblem1(w2, u, c)};
    if (g2 <= 0.0) break;  // one intermediate: the two pairs are the same
  }
  return out;
}

// A unit vector across w.
Vector3d Across(const Vector3d& w) {
  const Vector3d t = std::abs(w.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return w.cross(t).normalized();
}

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

// cos and sin of the 16 sample angles 2 pi s / 16, and the half-angle expansions
//     (1 + i t)^(d + m) (1 - i t)^(d - m) = sum_k B[d][m][k] t^k,   d = 1..4, m = 0..d,
// which turn a trigonometric polynomial of degree d in c into a real polynomial of degree 2 d in
// t = tan((c - c0) / 2): e^{i m (c - c0)} (1 + t^2)^d = (1 + i t)^(d + m) (1 - i t)^(d - m).
struct TrigTables {
  static constexpr int kSamples = 16;
  double cos[kSamples], sin[kSamples];
  std::complex<double> B[5][5][9] = {};
  TrigTables() {
    for (int s = 0; s < kSamples; ++s) {
      cos[s] = std::cos(2 * M_PI * s / kSamples);
      sin[s] = std::sin(2 * M_PI * s / kSamples);
    }
    for (int d = 1; d <= 4; ++d) {
      for (int m = 0; m <= d; ++m) {
        std::complex<double>* b = B[d][m];
        b[0] = 1.0;
        int degree = 0;
        for (int f = 0; f < 2 * d; ++f) {  // multiply by (1 + i t) d + m times, then by (1 - i t)
          const std::complex<double> slope(0.0, f < d + m ? 1.0 : -1.0);
          for (int k = degree + 1; k > 0; --k) b[k] += slope * b[k - 1];
          ++degree;
        }
      }
    }
  }
};
const TrigTables& Tables() {
  static const TrigTables tables;
  return tables;
}

// The roots z = e^{ic} (within 2 % of the unit circle) of z^degree F(z), from the complex companion
// matrix: the fallback of TrigRoots when its real Schur form does not converge.
FixedList<double, 8> ComplexCompanionAngles(const std::complex<double>* f, int degree) {
  const int N = 2 * degree;
  const auto coefficient = [&](int j) {
    const int m = j - degree;
    return m >= 0 ? f[m] : std::conj(f[-m]);
  };
  Eigen::MatrixXcd companion = Eigen::MatrixXcd::Zero(N, N);
  const std::complex<double> lead = coefficient(N);
  for (int j = 0; j < N; ++j) companion(0, N - 1 - j) = -coefficient(j) / lead;
  for (int j = 1; j < N; ++j) companion(j, j - 1) = 1.0;
  const Eigen::VectorXcd z = Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(companion, false).eigenvalues();
  FixedList<double, 8> out;
  for (int j = 0; j < N; ++j) {
    if (std::isfinite(z[j].real()) && std::abs(std::abs(z[j]) - 1.0) <= 2e-2) out.Push(std::arg(z[j]));
  }
  return out;
}

// The real roots c of the trigonometric polynomial F(c) = f0 + 2 Re sum_{m=1}^{degree} f_m e^{imc}, and
// the near-real ones (z = e^{ic} within 2 % of the unit circle, so that a pose just outside a fold still
// gets its nearest candidates; the callers check every candidate), unpolished.
// With t = tan((c - c0) / 2), P(t) = (1 + t^2)^degree F(c) is a real polynomial of degree 2 degree whose
// leading coefficient is F(c0 + pi): c0 + pi is the sample where |F| is largest, so P keeps its full
// degree and no root hides at t = infinity. Its roots are the eigenvalues of the companion matrix,
// already upper Hessenberg: a real Schur form of at most 8 x 8 of fixed capacity (the complex companion
// of z^degree F(z) in a dynamic matrix took about 3 times as many instructions).
FixedList<double, 8> TrigRoots(const std::complex<double>* f, int degree, double c_max) {
  const TrigTables& tables = Tables();
  const int N = 2 * degree;
  const double c0 = c_max - M_PI;
  double P[9] = {};
  for (int m = 0; m <= degree; ++m) {
    const std::complex<double> g = f[m] * std::polar(m == 0 ? 1.0 : 2.0, m * c0);  // f_-m terms: conjugates
    for (int k = 0; k <= N; ++k) P[k] += (g * tables.B[degree][m][k]).real();
  }
  using Matrix8 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 8, 8>;
  Matrix8 H = Matrix8::Zero(N, N);
  for (int j = 0; j < N; ++j) H(0, j) = -P[N - 1 - j] / P[N];
  for (int j = 1; j < N; ++j) H(j, j - 1) = 1.0;
  Eigen::RealSchur<Matrix8> schur(N);
  schur.computeFromHessenberg(H, H, false);
  if (schur.info() != Eigen::Success) return ComplexCompanionAngles(f, degree);
  const Matrix8& T = schur.matrixT();
  FixedList<double, 8> out;
  const auto add = [&](double re, double im) {
    // z = (1 + i t) / (1 - i t) = e^{i (c - c0)}.
    const std::complex<double> t(re, im), i(0.0, 1.0);
    const std::complex<double> z = (1.0 + i * t) / (1.0 - i * t);
    if (std::isfinite(z.real()) && std::isfinite(z.imag()) && std::abs(std::abs(z) - 1.0) <= 2e-2) {
      out.Push(c0 + std::arg(z));
    }
  };
  for (int j = 0; j < N;) {
    if (j + 1 < N && T(j + 1, j) != 0.0) {
      // A 2 x 2 block (complex pair; RealSchur splits blocks with real eigenvalues): Eigen's formula.
      const double p = 0.5 * (T(j, j) - T(j + 1, j + 1));
      const double t0 = T(j + 1, j), t1 = T(j, j + 1);
      const double scale = std::max({std::abs(p), std::abs(t0), std::abs(t1)});
      const double disc = (p / scale) * (p / scale) + (t0 / scale) * (t1 / scale);
      if (disc >= 0) {
        const double r = scale * std::sqrt(disc);
        add(T(j + 1, j + 1) + p + r, 0.0);
        add(T(j + 1, j + 1) + p - r, 0.0);
      } else {
        const double r = scale * std::sqrt(-disc);
        add(T(j + 1, j + 1) + p, r);
        add(T(j + 1, j + 1) + p, -r);
      }
      j += 2;
    } else {
      add(T(j, j), 0.0);
      ++j;
    }
  }
  return out;
}

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
using Positions = FixedList<Vector3d, 16>;
Positions Solve3R(Screw A, Screw B, const Screw& C, const Vector3d& p0, const Vector3d& p, const double free[3],
                  int* free_mask) {
  Positions out;
  const double kAB = A.w.dot(B.w);
  const bool parallel = 1 - kAB * kAB <= 1e-12;
  const double length = 1.0 + p.norm() + p0.norm();
  // Points on A and B at their common perpendicular (so that d = 0 when they meet), unless that is far
  // away (nearly parallel axes): the equations hold for any points, and far ones would cost precision.
  if (!parallel) {
    const Vector3d r = B.p - A.p;
    const double s = (A.w.dot(r) - kAB * B.w.dot(r)) / (1 - kAB * kAB);
    const double t = (kAB * A.w.dot(r) - B.w.dot(r)) / (1 - kAB * kAB);
    if (std::abs(s) <= 1e3 * length && std::abs(t) <= 1e3 * length) {
      A.p += s * A.w;
      B.p += t * B.w;
    }
  }
  const Vector3d d = B.p - A.p;
  const double rho = (p - A.p).squaredNorm(), h = A.w.dot(p - A.p);
  const Vector3d v = p0 - C.p;
  const Vector3d U1 = v - C.w * C.w.dot(v), U2 = C.w.cross(v), U0 = C.w * C.w.dot(v) + C.p - B.p;
  const double dwB = d.dot(B.w);
  struct Coef {
    double a1, b1, g1, a2, b2, g2;
  };
  const auto coef = [&](double cos_c, double sin_c) {
    const Vector3d u = U1 * cos_c + U2 * sin_c + U0;
    const double uwB = B.w.dot(u);
    const Vector3d wxu = B.w.cross(u);
    Coef k;
    k.a1 = 2 * (d.dot(u) - dwB * uwB);
    k.b1 = 2 * d.dot(wxu);
    k.g1 = u.squaredNorm() + d.squaredNorm() + 2 * dwB * uwB - rho;
    k.a2 = A.w.dot(u) - kAB * uwB;
    k.b2 = A.w.dot(wxu);
    k.g2 = kAB * uwB + A.w.dot(d) - h;
    return k;
  };
  // The first equation is in length^2, the second in length: both are compared divided by those.
  constexpr double kNegligible = 1e-10;
  FixedList<double, 8> roots;
  int b_from = 0;  // the equation(s) that give b: 0 both, 1 or 2 that one alone
  const auto push_root = [&](double c) {
    for (double r : roots) {
      if (std::abs(WrapAngle(r - c)) < 1e-12) return;
    }
    roots.Push(c);
  };
  const auto free_c = [&]() {
    *free_mask |= 4;
    push_root(free[2]);
  };
  // alpha cos x + beta sin x + gamma = 0 (in units of `scale`): <= 2 angles, or every angle (*all).
  const auto circle = [&](double alpha, double beta, double gamma, double scale, double* x, bool* all) {
    *all = false;
    const double r = std::hypot(alpha, beta);
    if (r <= kNegligible * scale) {
      *all = std::abs(gamma) <= kNegligible * scale;
      return 0;
    }
    if (std::abs(gamma) > r * (1 + 1e-9)) return 0;
    const double phi = std::atan2(beta, alpha), delta = std::acos(std::clamp(-gamma / r, -1.0, 1.0));
    x[0] = phi + delta;
    x[1] = phi - delta;
    return delta > 1e-12 && delta < M_PI - 1e-12 ? 2 : 1;
  };
  const auto eliminant_roots = [&]() {
    const TrigTables& tables = Tables();
    constexpr int kSamples = TrigTables::kSamples;
    double samples[kSamples];
    int largest = 0;
    double magnitude = 0.0;  // of the terms of F, which cancel where F vanishes identically
    for (int s = 0; s < kSamples; ++s) {
      const Coef k = coef(tables.cos[s], tables.sin[s]);
      const double x = k.b1 * k.g2 - k.b2 * k.g1, y = k.a2 * k.g1 - k.a1 * k.g2, D = k.a1 * k.b2 - k.a2 * k.b1;
      samples[s] = x * x + y * y - D * D;
      magnitude = std::max(magnitude, x * x + y * y + D * D);
      if (std::abs(samples[s]) > std::abs(samples[largest])) largest = s;
    }
    std::complex<double> f[5];  // f[m], m = 0..4; f[-m] = conj(f[m])
    double scale = 0.0;
    for (int m = 0; m <= 4; ++m) {
      double re = 0.0, im = 0.0;
      for (int s = 0; s < kSamples; ++s) {
        const int r = (m * s) % kSamples;  // e^{-2 pi i m s / 16}
        re += samples[s] * tables.cos[r];
        im -= samples[s] * tables.sin[r];
      }
      f[m] = std::complex<double>(re, im) / double(kSamples);
      scale = std::max(scale, std::abs(f[m]));
    }
    if (scale <= 1e-12 * magnitude) {
      // F vanishes identically (to rounding of its terms): every c has a solution.
      free_c();
      return;
    }
    int degree = 4;
    while (degree > 0 && std::abs(f[degree]) <= 1e-11 * scale) --degree;
    if (degree == 0) return;  // F is a constant other than 0: no solution
    const FixedList<double, 8> raw = TrigRoots(f, degree, 2 * M_PI * largest / kSamples);
    // F, dF/dc and d2F/dc2 from the Fourier series.
    const auto evaluate = [&](double c, double* slope, double* curvature) {
      const std::complex<double> e1 = std::polar(1.0, c);
      std::complex<double> e = 1.0;
      double value = f[0].real();
      *slope = *curvature = 0.0;
      for (int m = 1; m <= degree; ++m) {
        e *= e1;
        const std::complex<double> fe = f[m] * e;
        value += 2.0 * fe.real();
        *slope -= 2.0 * m * fe.imag();       // 2 Re(i m f_m e^{imc})
        *curvature -= 2.0 * m * m * fe.real();  // 2 Re(-m^2 f_m e^{imc})
      }
      return value;
    };
    for (double c : raw) {
      // Newton on F polishes the eigenvalue's angle; a step is kept only where it lowers |F|, since at a
      // double root (F >= 0 touching zero, as where axes A and B meet) value and slope are both rounding
      // noise and a full step can throw an accurate root away.
      double slope = 0.0, curvature = 0.0;
      double value = evaluate(c, &slope, &curvature);
      for (int it = 0; it < 4 && value != 0.0; ++it) {
        const double step = value / slope;
        if (!std::isfinite(step) || std::abs(step) > 0.1) break;
        double next_slope = 0.0, next_curvature = 0.0;
        const double next = evaluate(c - step, &next_slope, &next_curvature);
        if (!(std::abs(next) < std::abs(value))) break;
        c -= step;
        value = next;
        slope = next_slope;
        curvature = next_curvature;
      }
      // Newton on F stops about sqrt(eps) short of a double root (where two branches meet: a singular
      // configuration, whose joints the polish on the model can then not correct; rounding of F, about
      // 1e-16 of its terms' magnitude, splits it into two roots up to 1e-6 apart where a third root is
      // near). The root of F' within 1e-4 is the root to full precision, if F is no larger there beyond
      // that rounding. At a simple root any such move raises |F| by |F'| |step|, far above rounding,
      // and is refused; so is merging two true roots whose |F| between them exceeds that rounding.
      for (int it = 0; it < 3; ++it) {
        const double step = slope / curvature;
        if (!std::isfinite(step) || std::abs(step) > 1e-4 || step == 0.0) break;
        double next_slope = 0.0, next_curvature = 0.0;
        const double next = evaluate(c - step, &next_slope, &next_curvature);
        if (!(std::abs(next) <= std::abs(value) + 1e-13 * magnitude)) break;
        c -= step;
        value = next;
        slope = next_slope;
        curvature = next_curvature;
      }
      bool duplicate = false;
      for (double r : roots) duplicate = duplicate || std::abs(WrapAngle(r - c)) < 1e-7;
      if (!duplicate) roots.Push(c);
    }
  };
  if (parallel || d.norm() <= 1e-12 * length) {
    // A and B meet (the shoulders of the IRB 120 and the Puma 560): turns about B keep the distance to
    // the common point, so the first equation loses b and reads gamma1(c) = 0,
    //     2 U0.U1 cos c + 2 U0.U2 sin c + |U1|^2 + |U0|^2 - rho = 0   (U1 _|_ U2, |U1| = |U2|).
    // A and B parallel (the seed's arm with its flange axis vertical): turns about B keep the height along
    // A, so the second equation loses b and reads gamma2(c) = 0,
    //     kAB wB.U1 cos c + kAB wB.U2 sin c + kAB wB.U0 + wA.d - h = 0.
    double x[2];
    bool all = false;
    const int count = parallel ? circle(kAB * B.w.dot(U1), kAB * B.w.dot(U2), kAB * B.w.dot(U0) + A.w.dot(d) - h,
                                        length, x, &all)
                               : circle(2 * U0.dot(U1), 2 * U0.dot(U2), U1.squaredNorm() + U0.squaredNorm() - rho,
                                        length * length, x, &all);
    if (all) free_c();
    for (int i = 0; i < count; ++i) push_root(x[i]);
    // The other equation gives b: the one used for c has lost it (to within the rounding, or the small
    // angle of nearly parallel axes, which would make b from it arbitrary).
    b_from = parallel ? 1 : 2;
  } else {
    eliminant_roots();
  }
  for (double c : roots) {
    const Coef k = coef(std::cos(c), std::sin(c));
    double bs[2];
    int count = 0;
    const double L2 = length * length;
    const double n1 = std::hypot(k.a1, k.b1) / L2, n2 = std::hypot(k.a2, k.b2) / length;
    const double D = (k.a1 * k.b2 - k.a2 * k.b1) / (L2 * length);
    if (b_from == 0 && n1 > kNegligible && n2 > kNegligible && std::abs(D) > 1e-7 * n1 * n2) {
      bs[count++] = std::atan2((k.a2 * k.g1 - k.a1 * k.g2) / D, (k.b1 * k.g2 - k.b2 * k.g1) / D);
    } else {
      // The two equations are dependent in (cos b, sin b), or one has lost b: use the stronger one.
      bool all = false;
      const bool first = b_from == 0 ? n1 >= n2 : b_from == 1;
      count = first ? circle(k.a1 / L2, k.b1 / L2, k.g1 / L2, 1.0, bs, &all)
                    : circle(k.a2 / length, k.b2 / length, k.g2 / length, 1.0, bs, &all);
      if (all) {
        // Neither equation depends on b: E_C(c) p0 is on B (or A and B are one line), every b does if
        // both hold.
        if (std::abs(k.g1) > kNegligible * L2 || std::abs(k.g2) > kNegligible * length) continue;
        *free_mask |= 2;
        bs[count++] = free[1];
      }
    }
    for (int i = 0; i < count; ++i) {
      const double b = bs[i];
      const Vector3d fp = Exp(B, b) * (Exp(C, c) * p0);
      bool free_a = false;
      double a = Subproblem1(A.w, fp - A.p, p - A.p, &free_a);
      if (free_a) {
        *free_mask |= 1;
        a = free[0];
      }
      const Vector3d reached = Exp(A, a) * fp;
      if ((reached - p).norm() < 1e-4 * length) out.Push(Vector3d(a, b, c));
    }
  }
  return out;
}

// The point where three lines meet (least squares) and the largest distance of it to them.
Vector3d CommonPoint(const Screw* s, int count, double* distance) {
  Matrix3d A = Matrix3d::Zero();
  Vector3d b = Vector3d::Zero();
  for (int i = 0; i < count; ++i) {
    const Matrix3d P = Matrix3d::Identity() - s[i].w * s[i].w.transpose();
    A += P;
    b += P * s[i].p;
  }
  const Vector3d w = A.ldlt().solve(b);
  *distance = 0.0;
  for (int i = 0; i < count; ++i) {
    const Vector3d r = w - s[i].p;
    *distance = std::max(*distance, (r - s[i].w * s[i].w.dot(r)).norm());
  }
  if (!w.allFinite()) *distance = INFINITY;
  return w;
}

double LineDistance(const Screw& a, const Screw& b) {
  const Vector3d n = a.w.cross(b.w);
  const Vector3d r = b.p - a.p;
  if (n.norm() < 1e-12) return (r - a.w * a.w.dot(r)).norm();
  return std::abs(r.dot(n)) / n.norm();
}

}  // namespace

// Closed-form branches of a 6-joint arm: at most 16 positions of the 3R chain (8 roots, two angles
// where its equations are dependent) times 3 for the rest (2, and a free pair next to a singularity).
using BranchList = FixedList<Vector6d, 48>;

struct NominalInverseKinematics::Impl {
  enum class Kind { kNumeric, kPieper, kParallel };
  Robot robot;
  NominalIkOptions options;
  int n = 0;
  Kind kind = Kind::kNumeric;
  int first = 0;          // first joint (0-based, in the solved chain) of the triple
  bool reversed = false;  // the chain is solved backwards (T^-1, joints in reverse order)
  std::vector<Screw> screws;  // of the solved chain
  Isometry3d T0 = Isometry3d::Identity();  // of the solved chain
  Vector3d center = Vector3d::Zero();  // Pieper: where the triple meets; parallel: where the pair meets
  VectorXd middle;

  void Detect();
  // Raw closed-form branches (unpolished, unwrapped) in the model's joint order. Where a family of
  // solutions is continuous (a singular pose: two axes in line, a point on an axis), its free joint takes
  // its value from `free` (model order) and sets its bit (1 << joint) in *free_mask.
  BranchList Branches(const Isometry3d& T, const VectorXd& free, int* free_mask) const;
  // The same for the solved chain (reversed or not), `free` in its order, bits of its joints.
  void PieperBranches(const Isometry3d& M, const Vector6d& free, BranchList* out, int* free_mask) const;
  void ParallelBranches(const Isometry3d& M, const Vector6d& free, BranchList* out, int* free_mask) const;
  // The solution a controller takes among `branches` (ranked: inside the limits, the named
  // configuration, the distance to the reference), polished; false when none reaches the pose.
  // *unfinished: the polished joints of the first candidate inside the limits that did not reach it
  // (next to a singular configuration, where the closed form loses accuracy), else empty.
  bool Choose(const Isometry3d& T, const VectorXd& reference, BranchList* branches, IkSolution* s,
              VectorXd* unfinished = nullptr) const;
  // A pose whose solution family is continuous (free joints in free_mask) and whose member at the
  // reference leaves the limits: the member inside the limits whose free joint is closest to the
  // reference's (one free joint moved at a time); false when no member is inside.
  bool SearchFamily(const Isometry3d& T, const VectorXd& reference, int free_mask, IkSolution* s) const;
  // Newton on the model; returns the errors.
  void Polish(const Isometry3d& T, VectorXd* q, double* pe, double* oe) const;
  // Moves revolute joints by whole turns into their limits, to the representative closest to the
  // reference; a joint within kLimitSlack outside its limit (a solution on the limit, with the rounding
  // of the closed form or the polish) is clamped onto it, *clamped set when that moved a joint.
  bool WrapIntoLimits(const VectorXd& reference, Eigen::Ref<VectorXd> q, bool* clamped = nullptr) const;
  bool Singular(const VectorXd& q) const;
  bool MatchesConfiguration(const Eigen::Ref<const VectorXd>& q) const;
  // The numeric solver from `start` (the reference when empty), with `restarts` (< 0: the options').
  IkSolution Numeric(const Isometry3d& T, bool orientation, const VectorXd& reference, const VectorXd& start = {},
                     int restarts = -1) const;
};

void NominalInverseKinematics::Impl::Detect() {
  const KinematicModel& model = robot.model();
  if (n != 6 || !options.use_closed_form) return;
  for (int j = 0; j < n; ++j) {
    if (model.joint_type(j) != JointType::kRevolute) return;
  }
  const VectorXd zero = VectorXd::Zero(n);
  const Isometry3d T_zero = model.ForwardKinematics(zero);
  const Matrix6Xd J = model.JointJacobian(zero);
  std::vector<Screw> forward(n);
  double length = 1.0;
  for (int j = 0; j < n; ++j) {
    const Vector3d w = J.col(j).tail<3>(), v = J.col(j).head<3>();
    if (std::abs(w.norm() - 1) > 1e-9) return;
    forward[j] = {w, T_zero.translation() + w.cross(v)};
    length = std::max(length, forward[j].p.norm());
  }
  // The product of exponentials must be the model (it is for every serial chain of revolute joints).
  Rng rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    VectorXd q(n);
    for (int j = 0; j < n; ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    Isometry3d T = Isometry3d::Identity();
    for (int j = 0; j < n; ++j) T = T * Exp(forward[j], q[j]);
    T = T * T_zero;
    const Vector6d e = PoseError(T, model.ForwardKinematics(q));
    if (!(e.head<3>().norm() < 1e-9 * length && e.tail<3>().norm() < 1e-9)) return;
  }
  // The reversed chain: T^-1 = E'_n(q_n) ... E'_1(q_1) T0^-1 with E'_j = E of -(T0^-1 s_j).
  std::vector<Screw> backward(n);
  const Isometry3d T_inv = T_zero.inverse();
  for (int j = 0; j < n; ++j) backward[n - 1 - j] = {-(T_inv.linear() * forward[j].w), T_inv * forward[j].p};
  const double dtol = options.distance_tolerance, wtol = options.direction_tolerance;
  const auto parallel = [&](const Screw& a, const Screw& b) { return a.w.cross(b.w).norm() < wtol; };
  // Pieper: prefer the wrist (the last three), then the others.
  for (int t : {3, 0, 1, 2}) {
    if (parallel(forward[t], forward[t + 1]) || parallel(forward[t + 1], forward[t + 2])) continue;
    double distance = 0.0;
    const Vector3d w = CommonPoint(&forward[t], 3, &distance);
    if (distance < dtol * length) {
      kind = Kind::kPieper;
      first = t;
      screws = forward;
      T0 = T_zero;
      center = w;
      return;
    }
  }
  // Three parallel axes 2, 3, 4 with axes 5 and 6 meeting (or the mirror image, by reversal).
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<Screw>& s = pass == 0 ? forward : backward;
    if (!parallel(s[1], s[2]) || !parallel(s[2], s[3]) || parallel(s[0], s[1]) || parallel(s[4], s[5])) continue;
    if (LineDistance(s[1], s[2]) < dtol * length || LineDistance(s[2], s[3]) < dtol * length) continue;
    if (LineDistance(s[4], s[5]) > dtol * length) continue;
    double distance = 0.0;
    const Vector3d u = CommonPoint(&s[4], 2, &distance);
    kind = Kind::kParallel;
    first = 1;
    reversed = pass == 1;
    screws = s;
    T0 = pass == 0 ? T_zero : T_inv;
    center = u;
    return;
  }
}

void NominalInverseKinematics::Impl::PieperBranches(const Isometry3d& M, const Vector6d& free, BranchList* out,
                                                    int* free_mask) const {
  // Joints after the triple, moved by M, then those before: the 3R chain that takes w to M w.
  int outer[3];
  Screw chain[3];
  int k = 0;
  for (int j = first + 3; j < n; ++j, ++k) {
    outer[k] = j;
    chain[k] = Moved(M, screws[j]);
  }
  for (int j = 0; j < first; ++j, ++k) {
    outer[k] = j;
    chain[k] = screws[j];
  }
  const double free_outer[3] = {free[outer[0]], free[outer[1]], free[outer[2]]};
  int mask = 0;
  const Positions positions = Solve3R(chain[0], chain[1], chain[2], center, M * center, free_outer, &mask);
  for (int i = 0; i < 3; ++i) {
    if (mask & (1 << i)) *free_mask |= 1 << outer[i];
  }
  const Vector3d& w1 = screws[first].w;
  const Vector3d& w2 = screws[first + 1].w;
  const Vector3d& w3 = screws[first + 2].w;
  const Vector3d e = Across(w3);
  for (const Vector3d& abc : positions) {
    Vector6d q = Vector6d::Zero();
    for (int i = 0; i < 3; ++i) q[outer[i]] = abc[i];
    Isometry3d before = Isometry3d::Identity(), after = Isometry3d::Identity();
    for (int j = 0; j < first; ++j) before = before * Exp(screws[j], q[j]);
    for (int j = first + 3; j < n; ++j) after = after * Exp(screws[j], q[j]);
    const Matrix3d R_N = (before.inverse() * M * after.inverse()).linear();
    int wrist = 0;
    for (const auto& [x, y] : Subproblem2(w1, w2, w3, R_N * w3, free[first], free[first + 1], &wrist)) {
      q[first] = x;
      q[first + 1] = y;
      q[first + 2] = Subproblem1(w3, e, (Rot(w1, x) * Rot(w2, y)).transpose() * R_N * e);
      out->Push(q);
    }
    *free_mask |= wrist << first;
  }
}

void NominalInverseKinematics::Impl::ParallelBranches(const Isometry3d& M, const Vector6d& free, BranchList* out,
                                                      int* free_mask) const {
  const Screw &X = screws[0], &P1 = screws[1], &P2 = screws[2], &P3 = screws[3], &Y = screws[4], &Z = screws[5];
  const Vector3d& w = P1.w;
  const auto flat = [&](const Vector3d& x) { return Vector3d(x - w * w.dot(x)); };
  // The elbow takes the point of axis P3 (at s, distance r2 from axis P2) to a point at distance r1 from
  // axis P1: reachable for |dist - r2| <= r1 <= dist + r2.
  const Vector3d c1 = flat(P1.p), c2 = flat(P2.p);
  const Vector3d dv = c2 - c1;
  const double dist = dv.norm(), r2 = flat(P3.p - P2.p).norm();
  if (dist < 1e-12) return;  // P1 and P2 in line: not a closed-form arm (Detect)
  // Where the wrist is singular, the free angle x of screw S moves that point on the circle
  // t(x) = Q E_S(-x) g, in a plane across w: |flat(t) - c1|^2 = K + alpha cos x + beta sin x. The angle
  // closest to `reference` that keeps it within reach (the reference itself, else an edge of the arc).
  const auto reachable_free_angle = [&](const Isometry3d& Q, const Screw& S, const Vector3d& g, double reference) {
    const Vector3d on = S.p + S.w * S.w.dot(g - S.p), gp = g - on;
    const Vector3d o = flat(Q * on) - c1, U = flat(Q.linear() * gp), V = flat(Q.linear() * S.w.cross(gp));
    const double K = o.squaredNorm() + U.squaredNorm(), alpha = 2 * o.dot(U), beta = -2 * o.dot(V);
    const double low = (dist - r2) * (dist - r2), high = (dist + r2) * (dist + r2), tolerance = 1e-12 * high;
    const auto reachable = [&](double x) {
      const double r = K + alpha * std::cos(x) + beta * std::sin(x);
      return r >= low - tolerance && r <= high + tolerance;
    };
    if (reachable(reference)) return reference;
    double best = reference, best_distance = INFINITY;
    const double rho = std::hypot(alpha, beta), phi = std::atan2(beta, alpha);
    for (double edge : {low, high}) {
      if (!(rho > 0)) break;
      const double delta = std::acos(std::clamp((edge - K) / rho, -1.0, 1.0));
      for (double x : {phi + delta, phi - delta}) {
        const double distance = std::abs(WrapAngle(x - reference));
        if (distance < best_distance && reachable(x)) {
          best = x;
          best_distance = distance;
        }
      }
    }
    return best;
  };
  // The planar triple keeps heights along w: w.(E_X(-a) M u - u) = 0, with E_Y, E_Z fixing u.
  const Vector3d m = M * center - X.p;
  const double A = w.dot(m - X.w * X.w.dot(m)), B = -w.dot(X.w.cross(m));
  const double C = w.dot(center - X.p) - w.dot(X.w) * X.w.dot(m);
  const double r = std::hypot(A, B), length = 1.0 + m.norm() + center.norm();
  double as[2];
  int count = 0;
  if (r <= 1e-10 * length) {
    // The pair's point on axis X (a shoulder singularity): its height is the same for every a.
    if (std::abs(C) > 1e-10 * length) return;
    *free_mask |= 1;
    as[count++] = free[0];
  } else {
    if (std::abs(C) > r * (1 + 1e-9)) return;
    const double phi = std::atan2(B, A), delta = std::acos(std::clamp(C / r, -1.0, 1.0));
    as[count++] = phi + delta;
    if (delta > 1e-12 && delta < M_PI - 1e-12) as[count++] = phi - delta;
  }
  for (int i = 0; i < count; ++i) {
    const double a = as[i];
    // The triple keeps w: R_Y(y) R_Z(z) (R_M^T R_X(a) w) = w; y is free where w lies on Y (the wrist
    // singularity of the UR family: axes 4 and 6 in line), z where v lies on Z.
    const Vector3d v = M.linear().transpose() * Rot(X.w, a) * w;
    int wrist = 0;
    const AnglePairs pairs = Subproblem2(Y.w, Z.w, v, w, free[4], free[5], &wrist);
    *free_mask |= wrist << 4;
    for (int pair = 0; pair < pairs.size; ++pair) {
      auto [y, z] = pairs.pair[pair];
      // A free wrist angle moves the point of axis P3 (where the elbow must take it) on a circle in the
      // plane of the planar triple; only where that point is within the elbow's reach does it give a
      // solution, possibly at one angle alone (the elbow stretched there).
      if (pairs.free[pair] & 2) {
        z = reachable_free_angle(Exp(X, -a) * M, Z, Exp(Y, -y) * P3.p, free[5]);
      } else if (pairs.free[pair] & 1) {
        y = reachable_free_angle(Exp(X, -a) * M * Exp(Z, -z), Y, P3.p, free[4]);
      }
      const Isometry3d P = Exp(X, -a) * M * Exp(Z, -z) * Exp(Y, -y);
      // Elbow: the point of axis P3 goes from s to t by turns about P2 then P1 (circle intersection).
      const Vector3d s = P3.p, t = P * P3.p;
      const double r1 = flat(t - P1.p).norm();
      const double along = (r1 * r1 - r2 * r2 + dist * dist) / (2 * dist);
      double h2 = r1 * r1 - along * along;
      if (h2 < -1e-9 * (r1 * r1 + 1e-12)) continue;
      h2 = std::max(h2, 0.0);
      for (double sign : {1.0, -1.0}) {
        const Vector3d x = c1 + along * dv / dist + sign * std::sqrt(h2) * w.cross(dv) / dist;
        Vector6d q;
        q[0] = a;
        q[4] = y;
        q[5] = z;
        q[2] = Subproblem1(P2.w, s - P2.p, x - c2);
        bool free_1 = false;
        q[1] = Subproblem1(P1.w, x - c1, t - P1.p, &free_1);
        if (free_1) {
          // The elbow folded onto axis P1 (links of equal length): every turn about it does.
          q[1] = free[1];
          *free_mask |= 2;
        }
        const Vector3d e = Across(P3.w);
        q[3] = Subproblem1(P3.w, e, (Rot(P1.w, q[1]) * Rot(P2.w, q[2])).transpose() * P.linear() * e);
        out->Push(q);
        if (h2 == 0.0) break;  // one elbow
      }
    }
  }
}

BranchList NominalInverseKinematics::Impl::Branches(const Isometry3d& T, const VectorXd& free, int* free_mask) const {
  *free_mask = 0;
  BranchList out;
  if (kind == Kind::kNumeric) return out;
  const Isometry3d M = (reversed ? T.inverse() : T) * T0.inverse();
  // The reversed chain has the same joint angles in reverse order (see Detect).
  Vector6d chain_free = free;
  if (reversed) chain_free.reverseInPlace();
  int mask = 0;
  if (kind == Kind::kPieper) {
    PieperBranches(M, chain_free, &out, &mask);
  } else {
    ParallelBranches(M, chain_free, &out, &mask);
  }
  if (reversed) {
    for (int b = 0; b < out.size; ++b) out.item[b].reverseInPlace();
    int reversed_mask = 0;
    for (int j = 0; j < n; ++j) {
      if (mask & (1 << j)) reversed_mask |= 1 << (n - 1 - j);
    }
    mask = reversed_mask;
  }
  *free_mask = mask;
  return out;
}

void NominalInverseKinematics::Impl::Polish(const Isometry3d& T, VectorXd* q, double* pe, double* oe) const {
  const KinematicModel& model = robot.model();
  Vector6d e = PoseError(model.ForwardKinematics(*q), T);
  double cost = e.squaredNorm();
  for (int it = 0; it < 8 && cost > 1e-28; ++it) {
    const Matrix6Xd J = model.JointJacobian(*q);
    Eigen::MatrixXd H = J.transpose() * J;
    H.diagonal().array() += 1e-14 * std::max(1.0, H.diagonal().maxCoeff());
    const VectorXd step = H.ldlt().solve(J.transpose() * e);
    if (!step.allFinite()) break;
    const VectorXd trial = *q + step;
    const Vector6d e_trial = PoseError(model.ForwardKinematics(trial), T);
    if (!(e_trial.squaredNorm() < cost)) break;
    *q = trial;
    e = e_trial;
    cost = e.squaredNorm();
  }
  *pe = e.head<3>().norm();
  *oe = e.tail<3>().norm();
}

bool NominalInverseKinematics::Impl::WrapIntoLimits(const VectorXd& reference, Eigen::Ref<VectorXd> q,
                                                    bool* clamped) const {
  constexpr double kLimitSlack = 1e-9;  // rad
  bool inside = true;
  for (int j = 0; j < n; ++j) {
    const auto [low, high] = robot.Limit(j);
    double& v = q[j];
    if (robot.model().joint_type(j) == JointType::kRevolute) {
      // The representative v + 2 pi k inside [low, high] closest to the reference, else the one
      // closest to the interval.
      const double k_low = std::ceil((low - kLimitSlack - v) / (2 * M_PI));
      const double k_high = std::floor((high + kLimitSlack - v) / (2 * M_PI));
      if (k_low <= k_high) {
        const double k_ref = std::clamp(std::round((reference[j] - v) / (2 * M_PI)), k_low, k_high);
        v += 2 * M_PI * k_ref;
        if (v < low || v > high) {
          v = std::clamp(v, low, high);
          if (clamped) *clamped = true;
        }
        continue;
      }
      const double below = v + 2 * M_PI * (k_low - 1), above = v + 2 * M_PI * k_low;
      v = (low - below) < (above - high) ? below : above;
    }
    inside = inside && v >= low && v <= high;
  }
  return inside;
}

bool NominalInverseKinematics::Impl::Singular(const VectorXd& q) const {
  const Matrix6Xd J = robot.model().JointJacobian(q);
  if (J.cols() < 6) return true;
  if (J.cols() == 6) {
    // r = sigma_min / sigma_max is bracketed without an SVD: sigma_max <= |J|_F <= sqrt(6) sigma_max and
    // 1 / sigma_min <= |J^-1|_F <= sqrt(6) / sigma_min give r / 6 <= 1 / (|J|_F |J^-1|_F) <= r. Only a
    // ratio inside that factor of 6 of the threshold (or an exactly singular LU) needs the SVD.
    const Eigen::Matrix<double, 6, 6> A = J;
    const double bound = 1.0 / (A.norm() * Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>>(A).inverse().norm());
    if (bound >= options.singular_ratio) return false;
    if (6 * bound < options.singular_ratio) return true;
  }
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
  return s[s.size() - 1] < options.singular_ratio * s[0];
}

bool NominalInverseKinematics::Impl::MatchesConfiguration(const Eigen::Ref<const VectorXd>& q) const {
  for (size_t j = 0; j < options.configuration.size(); ++j) {
    const double v = WrapAngle(q[j]);
    if ((options.configuration[j] > 0 && v < 0) || (options.configuration[j] < 0 && v > 0)) return false;
  }
  return true;
}

IkSolution NominalInverseKinematics::Impl::Numeric(const Isometry3d& T, bool orientation, const VectorXd& reference,
                                                   const VectorXd& start, int restarts) const {
  InverseKinematicsOptions numeric = options.numeric;
  if (restarts >= 0) numeric.restarts = restarts;
  const InverseKinematicsResult r =
      SolveInverseKinematics(robot, T, orientation, start.size() == n ? start : reference, numeric);
  IkSolution s;
  s.q = r.q.allFinite() ? r.q : reference;
  s.position_error = std::isfinite(r.position_error) ? r.position_error : INFINITY;
  s.orientation_error = std::isfinite(r.orientation_error) ? r.orientation_error : INFINITY;
  const bool reached = s.position_error <= options.position_tolerance &&
                       (!orientation || s.orientation_error <= options.orientation_tolerance);
  // Not reached by any start: unreachable, whatever the configuration of the least error (next to a
  // pose out of reach it is the arm stretched towards it, singular).
  if (!reached) {
    s.status = IkStatus::kUnreachable;
    return s;
  }
  VectorXd q = s.q;
  const bool inside = WrapIntoLimits(reference, q);
  s.q = q;
  s.status = !inside ? IkStatus::kOutOfLimits : (orientation && Singular(q)) ? IkStatus::kSingular : IkStatus::kSolved;
  return s;
}

NominalInverseKinematics::NominalInverseKinematics(const Robot& robot, const NominalIkOptions& options)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("inverse kinematics: " + why);
  if (!robot.has_model()) throw std::invalid_argument("inverse kinematics: the robot has no model");
  impl_->robot = robot;
  impl_->options = options;
  impl_->n = robot.dof();
  if (!options.configuration.empty() && static_cast<int>(options.configuration.size()) != impl_->n) {
    throw std::invalid_argument("inverse kinematics: configuration needs one sign per joint");
  }
  impl_->middle.resize(impl_->n);
  for (int j = 0; j < impl_->n; ++j) {
    const auto [low, high] = robot.Limit(j);
    impl_->middle[j] = 0.5 * (low + high);
  }
  impl_->Detect();
}

NominalInverseKinematics::~NominalInverseKinematics() = default;

std::string NominalInverseKinematics::method() const {
  const int a = impl_->reversed ? impl_->n - impl_->first - 2 : impl_->first + 1;
  const std::string joints = std::to_string(a) + "," + std::to_string(a + 1) + "," + std::to_string(a + 2) + ")";
  switch (impl_->kind) {
    case Impl::Kind::kPieper: return "pieper(" + joints;
    case Impl::Kind::kParallel: return "parallel(" + joints;
    case Impl::Kind::kNumeric: break;
  }
  return "numeric";
}

bool NominalInverseKinematics::has_closed_form() const { return impl_->kind != Impl::Kind::kNumeric; }

bool NominalInverseKinematics::Impl::Choose(const Isometry3d& T, const VectorXd& ref, BranchList* branches,
                                            IkSolution* s, VectorXd* unfinished) const {
  if (unfinished) unfinished->resize(0);
  // Rank: inside the limits, then the named configuration, then the distance to the reference.
  struct Candidate {
    int rank;
    double distance;
    int branch;
  };
  Candidate candidates[BranchList::kCapacity];
  int count = 0;
  for (int b = 0; b < branches->size; ++b) {
    Vector6d& q = branches->item[b];
    if (!q.allFinite()) continue;
    const bool inside = WrapIntoLimits(ref, q);
    const int rank = (inside ? 0 : 2) + (MatchesConfiguration(q) ? 0 : 1);
    candidates[count++] = {rank, (q - ref).squaredNorm(), b};
  }
  std::sort(candidates, candidates + count, [](const Candidate& a, const Candidate& b) {
    return a.rank != b.rank ? a.rank < b.rank : a.distance < b.distance;
  });
  // The first candidate that reaches the pose inside the limits. One ranked inside before the polish may
  // end outside after it (next to a singular configuration the polish can move far): then the next
  // candidates, with the first that reached as the fallback.
  bool reached_outside = false;
  IkSolution fallback;
  for (int c = 0; c < count; ++c) {
    IkSolution t;
    t.q = branches->item[candidates[c].branch];
    t.branch = candidates[c].branch;
    t.closed_form = true;
    Polish(T, &t.q, &t.position_error, &t.orientation_error);
    if (!(t.position_error <= options.position_tolerance && t.orientation_error <= options.orientation_tolerance)) {
      if (unfinished && unfinished->size() == 0 && candidates[c].rank < 2) *unfinished = t.q;
      continue;
    }
    bool clamped = false;
    const bool inside = WrapIntoLimits(ref, t.q, &clamped);
    if (clamped) {
      // On a limit: the errors of the joints as returned.
      const Vector6d e = PoseError(robot.model().ForwardKinematics(t.q), T);
      t.position_error = e.head<3>().norm();
      t.orientation_error = e.tail<3>().norm();
      if (!(t.position_error <= options.position_tolerance && t.orientation_error <= options.orientation_tolerance)) {
        continue;
      }
    }
    if (inside) {
      t.status = Singular(t.q) ? IkStatus::kSingular : IkStatus::kSolved;
      *s = t;
      return true;
    }
    t.status = IkStatus::kOutOfLimits;
    if (!reached_outside) fallback = t;
    reached_outside = true;
    if (candidates[c].rank >= 2) break;  // the rest were outside before the polish too
  }
  if (reached_outside) *s = fallback;
  return reached_outside;
}

bool NominalInverseKinematics::Impl::SearchFamily(const Isometry3d& T, const VectorXd& ref, int free_mask,
                                                  IkSolution* s) const {
  // Whether a raw branch with free joint j at t reaches the pose (to the closed form's rounding, before the
  // polish) inside the limits; `strict`: without the slack that clamps a joint on a limit (the bisection
  // then ends inside, where the polished solution needs no clamp that would cost pose accuracy).
  VectorXd free = ref;
  const auto inside_at = [&](int j, double t, bool strict) {
    free[j] = t;
    int mask = 0;
    const BranchList branches = Branches(T, free, &mask);
    free[j] = ref[j];
    for (int b = 0; b < branches.size; ++b) {
      Vector6d q = branches.item[b];
      bool clamped = false;
      if (!q.allFinite() || !WrapIntoLimits(ref, q, &clamped) || (strict && clamped)) continue;
      const Vector6d e = PoseError(robot.model().ForwardKinematics(q), T);
      if (e.head<3>().norm() <= 1e-6 && e.tail<3>().norm() <= 1e-6) return true;
    }
    return false;
  };
  // Samples every 2 pi / 16 outwards from the reference's value, both ways; at the first inside, the
  // edge of the limits between it and the sample before (outside), by bisection to ~4e-13 rad.
  constexpr int kSamples = 16;
  constexpr double kStep = 2 * M_PI / kSamples;
  int best_joint = -1;
  double best_shift = INFINITY;
  for (int j = 0; j < n; ++j) {
    if (!(free_mask & (1 << j))) continue;
    bool found = false;
    for (int k = 1; k <= kSamples / 2 && !found; ++k) {
      for (double sign : {1.0, -1.0}) {
        if (k == kSamples / 2 && sign < 0) continue;  // the same sample as +pi
        if (k * kStep > std::abs(best_shift) + kStep) break;
        if (!inside_at(j, ref[j] + sign * k * kStep, false)) continue;
        found = true;
        double outside = sign * (k - 1) * kStep, inside = sign * k * kStep;
        for (int it = 0; it < 40; ++it) {
          const double mid = 0.5 * (outside + inside);
          (inside_at(j, ref[j] + mid, true) ? inside : outside) = mid;
        }
        if (std::abs(inside) < std::abs(best_shift)) {
          best_shift = inside;
          best_joint = j;
        }
      }
    }
  }
  if (best_joint < 0) return false;
  free[best_joint] = ref[best_joint] + best_shift;
  int mask = 0;
  BranchList branches = Branches(T, free, &mask);
  return Choose(T, ref, &branches, s) && s->status != IkStatus::kOutOfLimits;
}

std::vector<IkSolution> NominalInverseKinematics::AllBranches(const Isometry3d& T, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd& ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  std::vector<IkSolution> out;
  int free_mask = 0;
  const BranchList branches = m.Branches(T, ref, &free_mask);
  for (int b = 0; b < branches.size; ++b) {
    IkSolution s;
    s.q = branches.item[b];
    if (!s.q.allFinite()) continue;
    s.branch = b;
    s.closed_form = true;
    m.Polish(T, &s.q, &s.position_error, &s.orientation_error);
    if (!(s.position_error <= m.options.position_tolerance && s.orientation_error <= m.options.orientation_tolerance)) continue;
    const bool inside = m.WrapIntoLimits(ref, s.q);
    s.status = !inside ? IkStatus::kOutOfLimits : m.Singular(s.q) ? IkStatus::kSingular : IkStatus::kSolved;
    bool duplicate = false;
    for (const IkSolution& o : out) {
      VectorXd d = o.q - s.q;
      for (int j = 0; j < m.n; ++j) d[j] = WrapAngle(d[j]);
      duplicate = duplicate || d.cwiseAbs().maxCoeff() < 1e-6;
    }
    if (!duplicate) out.push_back(s);
  }
  return out;
}

IkSolution NominalInverseKinematics::Solve(const Isometry3d& T, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd& ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  int free_mask = 0;
  BranchList branches = m.Branches(T, ref, &free_mask);
  IkSolution s;
  VectorXd unfinished;
  const bool reached = m.Choose(T, ref, &branches, &s, &unfinished);
  if (reached && s.status != IkStatus::kOutOfLimits) return s;
  // A continuum of solutions whose member with the free joint at the reference leaves the limits: the
  // free joint moves as little as the limits require.
  IkSolution inside;
  if (reached && free_mask != 0 && m.SearchFamily(T, ref, free_mask, &inside)) return inside;
  // A candidate inside the limits that the polish could not finish: within about 1e-8 rad of a singular
  // configuration, where the closed form's free member (or its general solution) misses by ~1e-9.
  // The numeric solver, from there.
  if (unfinished.size() == m.n) {
    inside = m.Numeric(T, true, ref, unfinished, 0);
    if (inside.status == IkStatus::kSolved || inside.status == IkStatus::kSingular) return inside;
  }
  if (reached) return s;
  // No closed form, or no branch reaches the pose (out of reach, or rounding at the edge): numeric.
  return m.Numeric(T, true, ref);
}

IkSolution NominalInverseKinematics::SolvePosition(const Vector3d& p, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  Isometry3d T = Isometry3d::Identity();
  T.translation() = p;
  return m.Numeric(T, false, ref);
}

}  // namespace kincal
