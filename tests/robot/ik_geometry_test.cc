// The geometry under the closed-form inverse kinematics (robot/ik_geometry.h): PolynomialRoots, the
// fallback of the 3R eigenvalue solver, against polynomials built from known roots (simple, complex,
// clustered, double), random polynomials by their residuals and Vieta's sums, and refused input.
#include <algorithm>
#include <complex>
#include <vector>

#include <gtest/gtest.h>

#include "framework/random.h"
#include "robot/ik_geometry.h"

namespace kincal {
namespace {

using Complex = std::complex<double>;

// The coefficients (lowest first) of lead * prod (t - r_i); the roots come in conjugate pairs, so the
// imaginary parts cancel to rounding.
std::vector<double> FromRoots(const std::vector<Complex>& roots, double lead) {
  std::vector<Complex> c = {lead};
  for (const Complex& r : roots) {
    std::vector<Complex> next(c.size() + 1, 0.0);
    for (size_t k = 0; k < c.size(); ++k) {
      next[k + 1] += c[k];
      next[k] -= r * c[k];
    }
    c = next;
  }
  std::vector<double> P;
  for (const Complex& x : c) P.push_back(x.real());
  return P;
}

// The largest distance from a known root to the nearest root found.
double WorstMatch(const std::vector<Complex>& known, const Complex* found, int count) {
  double worst = 0.0;
  for (const Complex& r : known) {
    double best = INFINITY;
    for (int i = 0; i < count; ++i) best = std::min(best, std::abs(found[i] - r));
    worst = std::max(worst, best / (1.0 + std::abs(r)));
  }
  return worst;
}

TEST(PolynomialRoots, FindsKnownSimpleRealAndComplexRoots) {
  const std::vector<Complex> known = {-3.0, 0.5, {2.0, 1.0}, {2.0, -1.0}, 1e-3, 7.0, {-0.25, 4.0}, {-0.25, -4.0}};
  for (int degree = 1; degree <= 8; ++degree) {
    // Leading subsets that keep conjugate pairs together.
    if (degree == 3 || degree == 7) continue;
    const std::vector<Complex> roots(known.begin(), known.begin() + degree);
    const std::vector<double> P = FromRoots(roots, -2.5);
    Complex found[8];
    ASSERT_EQ(ik::PolynomialRoots(P.data(), degree, found), degree);
    EXPECT_LT(WorstMatch(roots, found, degree), 1e-12) << "degree " << degree;
  }
}

TEST(PolynomialRoots, DoubleAndClusteredRootsToTheirConditioning) {
  // A double root is found to about sqrt(eps) of its size; a simple root to eps |P|_1 / |P'(r)|, which for
  // three roots 1e-4 apart (P'(1) = -6e-8 with lead 3, |P|_1 about 24) is about 1e-7.
  Complex found[8];
  const std::vector<Complex> doubled = {1.0, 1.0, -2.0, {0.0, 3.0}, {0.0, -3.0}};
  const std::vector<double> P = FromRoots(doubled, 1.0);
  ASSERT_EQ(ik::PolynomialRoots(P.data(), 5, found), 5);
  EXPECT_LT(WorstMatch(doubled, found, 5), 1e-7);
  const std::vector<Complex> cluster = {1.0, 1.0 + 1e-4, 1.0 - 1e-4, -1.0};
  const std::vector<double> Q = FromRoots(cluster, 3.0);
  ASSERT_EQ(ik::PolynomialRoots(Q.data(), 4, found), 4);
  EXPECT_LT(WorstMatch(cluster, found, 4), 1e-6);
}

TEST(PolynomialRoots, RandomPolynomialsSatisfyResidualsAndVieta) {
  Rng rng(20261127);
  for (int trial = 0; trial < 500; ++trial) {
    const int degree = 1 + trial % 8;
    std::vector<double> P(degree + 1);
    for (double& p : P) p = rng.Normal() * std::pow(10.0, rng.Uniform(-3, 3));
    Complex found[8];
    ASSERT_EQ(ik::PolynomialRoots(P.data(), degree, found), degree);
    Complex sum = 0.0, product = 1.0;
    for (int i = 0; i < degree; ++i) {
      Complex value = 0.0;
      double size = 0.0;  // of the terms, which bounds the rounding of the value
      for (int k = degree; k >= 0; --k) {
        value = value * found[i] + P[k];
        size += std::abs(P[k]) * std::pow(std::abs(found[i]), k);
      }
      EXPECT_LE(std::abs(value), 1e-11 * size) << "trial " << trial << " root " << i;
      sum += found[i];
      product *= found[i];
    }
    const double lead = P[degree];
    double scale = 0.0;
    for (int i = 0; i < degree; ++i) scale += std::abs(found[i]);
    EXPECT_NEAR(std::abs(sum + P[degree - 1] / lead), 0.0, 1e-9 * (1.0 + scale)) << "trial " << trial;
    const double sign = degree % 2 == 0 ? 1.0 : -1.0;
    EXPECT_NEAR(std::abs(product - sign * P[0] / lead), 0.0, 1e-8 * (1.0 + std::abs(product))) << "trial " << trial;
  }
}

TEST(PolynomialRoots, RefusesAZeroOrNonFiniteLeadingCoefficient) {
  Complex found[8];
  const double zero_lead[3] = {1.0, 2.0, 0.0};
  EXPECT_EQ(ik::PolynomialRoots(zero_lead, 2, found), 0);
  const double nan_lead[3] = {1.0, 2.0, NAN};
  EXPECT_EQ(ik::PolynomialRoots(nan_lead, 2, found), 0);
  EXPECT_EQ(ik::PolynomialRoots(zero_lead, 0, found), 0);
}

}  // namespace
}  // namespace kincal
