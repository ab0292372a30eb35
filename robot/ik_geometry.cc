#include "robot/ik_geometry.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "framework/math.h"

namespace kincal::ik {

double Subproblem1(const Vector3d& w, const Vector3d& x, const Vector3d& y, bool* degenerate, CosSin* cs) {
  const Vector3d xp = x - w * w.dot(x), yp = y - w * w.dot(y);
  if (degenerate) *degenerate = xp.norm() < 1e-12 * (1.0 + x.norm());
  const double s = w.dot(xp.cross(yp)), c = xp.dot(yp);
  if (cs) {
    const double r = std::sqrt(c * c + s * s);  // products of lengths: no overflow; hypot costs 5 times more
    const double inverse = 1.0 / r;
    *cs = r > 0.0 ? CosSin{c * inverse, s * inverse} : CosSin{};
  }
  return std::atan2(s, c);
}

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
    const int i = out.size++;
    out.cs[i][0] = CosSin::Of(free_a);
    out.pair[i] = {free_a, Subproblem1(w2, u, v, nullptr, &out.cs[i][1])};
    if (across_v < 1e-12) return out;
  } else if (across_u < 1e-7) {
    *free |= 2;
    out.free[out.size] = 2;
    const int i = out.size++;
    out.cs[i][1] = CosSin::Of(free_b);
    out.pair[i] = {Subproblem1(w1, u, v, nullptr, &out.cs[i][0]), free_b};
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
    const int i = out.size++;
    out.pair[i] = {Subproblem1(w1, c, v, nullptr, &out.cs[i][0]), Subproblem1(w2, u, c, nullptr, &out.cs[i][1])};
    if (g2 <= 0.0) break;  // one intermediate: the two pairs are the same
  }
  return out;
}

Vector3d Across(const Vector3d& w) {
  const Vector3d t = std::abs(w.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return w.cross(t).normalized();
}

int PolynomialRoots(const double* P, int degree, std::complex<double>* roots) {
  const int N = degree;
  if (N < 1 || !(P[N] != 0.0) || !std::isfinite(P[N])) return 0;
  // Start on a circle of Fujiwara's bound on the roots' size, turned off the real axis (a real
  // polynomial's roots are symmetric about it, and starts on it would stay on it).
  double radius = 0.0;
  for (int k = 0; k < N; ++k) radius = std::max(radius, std::pow(std::abs(P[k] / P[N]), 1.0 / (N - k)));
  radius = radius > 0.0 && std::isfinite(radius) ? 2.0 * radius : 1.0;
  for (int i = 0; i < N; ++i) roots[i] = std::polar(radius, 2.0 * M_PI * i / N + 0.4);
  for (int iteration = 0; iteration < 200; ++iteration) {
    double largest_step = 0.0;
    for (int i = 0; i < N; ++i) {
      const std::complex<double> z = roots[i];
      std::complex<double> p = P[N], slope = 0.0;  // Horner: P(z) and P'(z)
      for (int k = N - 1; k >= 0; --k) {
        slope = slope * z + p;
        p = p * z + P[k];
      }
      if (p == 0.0) continue;
      const std::complex<double> newton = p / slope;
      std::complex<double> repulsion = 0.0;
      for (int j = 0; j < N; ++j) {
        if (j != i) repulsion += 1.0 / (z - roots[j]);
      }
      const std::complex<double> step = newton / (1.0 - newton * repulsion);
      if (!std::isfinite(step.real()) || !std::isfinite(step.imag())) continue;
      roots[i] -= step;
      largest_step = std::max(largest_step, std::abs(step) / std::max(1.0, std::abs(roots[i])));
    }
    if (largest_step <= 1e-15) break;
  }
  return N;
}

namespace {

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

// The real roots c of the trigonometric polynomial F(c) = f0 + 2 Re sum_{m=1}^{degree} f_m e^{imc}, and
// the near-real ones (z = e^{ic} within 2 % of the unit circle, so that a pose just outside a fold still
// gets its nearest candidates; the callers check every candidate), unpolished.
// With t = tan((c - c0) / 2), P(t) = (1 + t^2)^degree F(c) is a real polynomial of degree 2 degree whose
// leading coefficient is F(c0 + pi): c0 + pi is the sample where |F| is largest, so P keeps its full
// degree and no root hides at t = infinity. Its roots are the eigenvalues of the companion matrix,
// already upper Hessenberg: a real Schur form of at most 8 x 8 of fixed capacity (the complex companion
// of z^degree F(z) in a dynamic matrix took about 3 times as many instructions). Where that form does not
// converge, PolynomialRoots.
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
  FixedList<double, 8> out;
  const auto add = [&](double re, double im) {
    // z = (1 + i t) / (1 - i t) = e^{i (c - c0)}.
    const std::complex<double> t(re, im), i(0.0, 1.0);
    const std::complex<double> z = (1.0 + i * t) / (1.0 - i * t);
    if (std::isfinite(z.real()) && std::isfinite(z.imag()) && std::abs(std::abs(z) - 1.0) <= 2e-2) {
      out.Push(c0 + std::arg(z));
    }
  };
  if (schur.info() != Eigen::Success) {
    std::complex<double> roots[8];
    const int count = PolynomialRoots(P, N, roots);
    for (int j = 0; j < count; ++j) add(roots[j].real(), roots[j].imag());
    return out;
  }
  const Matrix8& T = schur.matrixT();
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

// The first equation is in length^2, the second in length: both are compared divided by those.
constexpr double kNegligible = 1e-10;

// alpha cos x + beta sin x + gamma = 0 (in units of `scale`): <= 2 angles into x, or every angle (*all).
int CircleAngles(double alpha, double beta, double gamma, double scale, double* x, bool* all) {
  *all = false;
  const double r = std::sqrt(alpha * alpha + beta * beta);  // lengths (squared): no overflow
  if (r <= kNegligible * scale) {
    *all = std::abs(gamma) <= kNegligible * scale;
    return 0;
  }
  if (std::abs(gamma) > r * (1 + 1e-9)) return 0;
  const double phi = std::atan2(beta, alpha), delta = std::acos(std::clamp(-gamma / r, -1.0, 1.0));
  x[0] = phi + delta;
  x[1] = phi - delta;
  return delta > 1e-12 && delta < M_PI - 1e-12 ? 2 : 1;
}

// Pieper's two equations of the 3R problem (Solve3R), alpha_i(c) cos b + beta_i(c) sin b + gamma_i(c) = 0,
// with A and B moved to their common perpendicular (so that d = 0 when they meet), unless that is far
// away (nearly parallel axes): the equations hold for any points, and far ones would cost precision.
struct PieperEquations {
  struct Coef {
    double a1, b1, g1, a2, b2, g2;
  };
  Screw A, B;
  double kAB, length, rho, h, dwB;
  bool parallel;
  Vector3d d, U0, U1, U2;

  PieperEquations(Screw a, Screw b, const Screw& C, const Vector3d& p0, const Vector3d& p) : A(a), B(b) {
    kAB = A.w.dot(B.w);
    parallel = 1 - kAB * kAB <= 1e-12;
    length = 1.0 + p.norm() + p0.norm();
    if (!parallel) {
      const Vector3d r = B.p - A.p;
      const double s = (A.w.dot(r) - kAB * B.w.dot(r)) / (1 - kAB * kAB);
      const double t = (kAB * A.w.dot(r) - B.w.dot(r)) / (1 - kAB * kAB);
      if (std::abs(s) <= 1e3 * length && std::abs(t) <= 1e3 * length) {
        A.p += s * A.w;
        B.p += t * B.w;
      }
    }
    d = B.p - A.p;
    rho = (p - A.p).squaredNorm();
    h = A.w.dot(p - A.p);
    const Vector3d v = p0 - C.p;
    U1 = v - C.w * C.w.dot(v);
    U2 = C.w.cross(v);
    U0 = C.w * C.w.dot(v) + C.p - B.p;
    dwB = d.dot(B.w);
  }

  Coef At(double cos_c, double sin_c) const {
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
  }
};

// The roots c of the 3R problem and the equation(s) that give b for them (Solve3R).
struct InnerAngles {
  FixedList<double, 8> roots;
  int b_from = 0;  // the equation(s) that give b: 0 both, 1 or 2 that one alone
  void Push(double c) {
    for (double r : roots) {
      if (std::abs(WrapAngle(r - c)) < 1e-12) return;
    }
    roots.Push(c);
  }
  // Every c has a solution: the free joint's value, its bit (4) in *free_mask.
  void Free(double c, int* free_mask) {
    *free_mask |= 4;
    Push(c);
  }
};

// The Fourier coefficients f[0..4] of the eliminant F(c) (Solve3R) from its 16 samples; *magnitude: the
// largest size of its terms (which cancel where F vanishes identically), *largest: the sample of largest
// |F|. Returns the largest |f[m]|.
double EliminantSeries(const PieperEquations& eq, std::complex<double>* f, double* magnitude, int* largest) {
  const TrigTables& tables = Tables();
  constexpr int kSamples = TrigTables::kSamples;
  double samples[kSamples];
  *largest = 0;
  *magnitude = 0.0;
  for (int s = 0; s < kSamples; ++s) {
    const PieperEquations::Coef k = eq.At(tables.cos[s], tables.sin[s]);
    const double x = k.b1 * k.g2 - k.b2 * k.g1, y = k.a2 * k.g1 - k.a1 * k.g2, D = k.a1 * k.b2 - k.a2 * k.b1;
    samples[s] = x * x + y * y - D * D;
    *magnitude = std::max(*magnitude, x * x + y * y + D * D);
    if (std::abs(samples[s]) > std::abs(samples[*largest])) *largest = s;
  }
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
  return scale;
}

// F, dF/dc and d2F/dc2 of the Fourier series f[0..degree] (f[-m] = conj(f[m])) at c.
double EvaluateSeries(const std::complex<double>* f, int degree, double c, double* slope, double* curvature) {
  const std::complex<double> e1 = std::polar(1.0, c);
  std::complex<double> e = 1.0;
  double value = f[0].real();
  *slope = *curvature = 0.0;
  for (int m = 1; m <= degree; ++m) {
    e *= e1;
    const std::complex<double> fe = f[m] * e;
    value += 2.0 * fe.real();
    *slope -= 2.0 * m * fe.imag();          // 2 Re(i m f_m e^{imc})
    *curvature -= 2.0 * m * m * fe.real();  // 2 Re(-m^2 f_m e^{imc})
  }
  return value;
}

// A root c of the eigenvalue solver polished on the series F.
double PolishRoot(const std::complex<double>* f, int degree, double magnitude, double c) {
  // Newton on F polishes the eigenvalue's angle; a step is kept only where it lowers |F|, since at a
  // double root (F >= 0 touching zero, as where axes A and B meet) value and slope are both rounding
  // noise and a full step can throw an accurate root away.
  double slope = 0.0, curvature = 0.0;
  double value = EvaluateSeries(f, degree, c, &slope, &curvature);
  for (int it = 0; it < 4 && value != 0.0; ++it) {
    const double step = value / slope;
    if (!std::isfinite(step) || std::abs(step) > 0.1) break;
    double next_slope = 0.0, next_curvature = 0.0;
    const double next = EvaluateSeries(f, degree, c - step, &next_slope, &next_curvature);
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
    const double next = EvaluateSeries(f, degree, c - step, &next_slope, &next_curvature);
    if (!(std::abs(next) <= std::abs(value) + 1e-13 * magnitude)) break;
    c -= step;
    value = next;
    slope = next_slope;
    curvature = next_curvature;
  }
  return c;
}

// The general case: the roots of the eliminant F(c), polished, into *angles.
void EliminantRoots(const PieperEquations& eq, double free_c, InnerAngles* angles, int* free_mask) {
  std::complex<double> f[5];  // f[m], m = 0..4; f[-m] = conj(f[m])
  double magnitude = 0.0;
  int largest = 0;
  const double scale = EliminantSeries(eq, f, &magnitude, &largest);
  if (scale <= 1e-12 * magnitude) {
    // F vanishes identically (to rounding of its terms): every c has a solution.
    angles->Free(free_c, free_mask);
    return;
  }
  int degree = 4;
  while (degree > 0 && std::abs(f[degree]) <= 1e-11 * scale) --degree;
  if (degree == 0) return;  // F is a constant other than 0: no solution
  const FixedList<double, 8> raw = TrigRoots(f, degree, 2 * M_PI * largest / TrigTables::kSamples);
  for (double c : raw) {
    c = PolishRoot(f, degree, magnitude, c);
    bool duplicate = false;
    for (double r : angles->roots) duplicate = duplicate || std::abs(WrapAngle(r - c)) < 1e-7;
    if (!duplicate) angles->roots.Push(c);
  }
}

// A and B meet (the shoulders of the IRB 120 and the Puma 560): turns about B keep the distance to
// the common point, so the first equation loses b and reads gamma1(c) = 0,
//     2 U0.U1 cos c + 2 U0.U2 sin c + |U1|^2 + |U0|^2 - rho = 0   (U1 _|_ U2, |U1| = |U2|).
// A and B parallel (the seed's arm with its flange axis vertical): turns about B keep the height along
// A, so the second equation loses b and reads gamma2(c) = 0,
//     kAB wB.U1 cos c + kAB wB.U2 sin c + kAB wB.U0 + wA.d - h = 0.
void SingleEquationRoots(const PieperEquations& eq, double free_c, InnerAngles* angles, int* free_mask) {
  const Screw &A = eq.A, &B = eq.B;
  const Vector3d &U0 = eq.U0, &U1 = eq.U1, &U2 = eq.U2;
  const double length = eq.length;
  double x[2];
  bool all = false;
  const int count = eq.parallel ? CircleAngles(eq.kAB * B.w.dot(U1), eq.kAB * B.w.dot(U2),
                                               eq.kAB * B.w.dot(U0) + A.w.dot(eq.d) - eq.h, length, x, &all)
                                : CircleAngles(2 * U0.dot(U1), 2 * U0.dot(U2),
                                               U1.squaredNorm() + U0.squaredNorm() - eq.rho, length * length, x, &all);
  if (all) angles->Free(free_c, free_mask);
  for (int i = 0; i < count; ++i) angles->Push(x[i]);
  // The other equation gives b: the one used for c has lost it (to within the rounding, or the small
  // angle of nearly parallel axes, which would make b from it arbitrary).
  angles->b_from = eq.parallel ? 1 : 2;
}

// The angles b for one root c (<= 2); false where no b solves both equations.
bool OuterAngles(const PieperEquations::Coef& k, double length, int b_from, double free_b, double* bs, int* count,
                 int* free_mask) {
  *count = 0;
  const double L2 = length * length;
  const double n1 = std::sqrt(k.a1 * k.a1 + k.b1 * k.b1) / L2, n2 = std::sqrt(k.a2 * k.a2 + k.b2 * k.b2) / length;
  const double D = (k.a1 * k.b2 - k.a2 * k.b1) / (L2 * length);
  if (b_from == 0 && n1 > kNegligible && n2 > kNegligible && std::abs(D) > 1e-7 * n1 * n2) {
    bs[(*count)++] = std::atan2((k.a2 * k.g1 - k.a1 * k.g2) / D, (k.b1 * k.g2 - k.b2 * k.g1) / D);
    return true;
  }
  // The two equations are dependent in (cos b, sin b), or one has lost b: use the stronger one.
  bool all = false;
  const bool first = b_from == 0 ? n1 >= n2 : b_from == 1;
  *count = first ? CircleAngles(k.a1 / L2, k.b1 / L2, k.g1 / L2, 1.0, bs, &all)
                 : CircleAngles(k.a2 / length, k.b2 / length, k.g2 / length, 1.0, bs, &all);
  if (all) {
    // Neither equation depends on b: E_C(c) p0 is on B (or A and B are one line), every b does if
    // both hold.
    if (std::abs(k.g1) > kNegligible * L2 || std::abs(k.g2) > kNegligible * length) return false;
    *free_mask |= 2;
    bs[(*count)++] = free_b;
  }
  return true;
}

}  // namespace

Positions Solve3R(Screw A, Screw B, const Screw& C, const Vector3d& p0, const Vector3d& p, const double free[3],
                  int* free_mask, FixedList<Matrix3d, 16>* rotations) {
  const PieperEquations eq(A, B, C, p0, p);
  InnerAngles angles;
  if (eq.parallel || eq.d.norm() <= 1e-12 * eq.length) {
    SingleEquationRoots(eq, free[2], &angles, free_mask);
  } else {
    EliminantRoots(eq, free[2], &angles, free_mask);
  }
  Positions out;
  for (double c : angles.roots) {
    double bs[2];
    int count = 0;
    const CosSin cs_c = CosSin::Of(c);
    if (!OuterAngles(eq.At(cs_c.c, cs_c.s), eq.length, angles.b_from, free[1], bs, &count, free_mask)) continue;
    const Matrix3d R_c = Rot(C.w, cs_c);
    const Vector3d moved_c = R_c * (p0 - C.p) + C.p;  // E_C(c) p0
    for (int i = 0; i < count; ++i) {
      const double b = bs[i];
      const Matrix3d R_b = Rot(eq.B.w, b);
      const Vector3d fp = R_b * (moved_c - eq.B.p) + eq.B.p;
      bool free_a = false;
      CosSin cs_a;
      double a = Subproblem1(eq.A.w, fp - eq.A.p, p - eq.A.p, &free_a, &cs_a);
      if (free_a) {
        *free_mask |= 1;
        a = free[0];
        cs_a = CosSin::Of(a);
      }
      const Matrix3d R_a = Rot(eq.A.w, cs_a);
      const Vector3d reached = R_a * (fp - eq.A.p) + eq.A.p;
      if ((reached - p).norm() < 1e-4 * eq.length) {
        out.Push(Vector3d(a, b, c));
        if (rotations) rotations->Push(R_a * R_b * R_c);
      }
    }
  }
  return out;
}

double PlanarElbow::ReachableFreeAngle(const Isometry3d& Q, const Screw& S, const Vector3d& g, double reference) const {
  const Vector3d on = S.p + S.w * S.w.dot(g - S.p), gp = g - on;
  const Vector3d o = Flat(Q * on) - c1, U = Flat(Q.linear() * gp), V = Flat(Q.linear() * S.w.cross(gp));
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
}

int ShoulderAngles(const Screw& X, const Vector3d& w, const Isometry3d& M, const Vector3d& center, double free_a,
                   double* as, int* free_mask) {
  const Vector3d m = M * center - X.p;
  const double A = w.dot(m - X.w * X.w.dot(m)), B = -w.dot(X.w.cross(m));
  const double C = w.dot(center - X.p) - w.dot(X.w) * X.w.dot(m);
  const double r = std::hypot(A, B), length = 1.0 + m.norm() + center.norm();
  int count = 0;
  if (r <= 1e-10 * length) {
    if (std::abs(C) > 1e-10 * length) return 0;
    *free_mask |= 1;
    as[count++] = free_a;
  } else {
    if (std::abs(C) > r * (1 + 1e-9)) return 0;
    const double phi = std::atan2(B, A), delta = std::acos(std::clamp(C / r, -1.0, 1.0));
    as[count++] = phi + delta;
    if (delta > 1e-12 && delta < M_PI - 1e-12) as[count++] = phi - delta;
  }
  return count;
}

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

}  // namespace kincal::ik
