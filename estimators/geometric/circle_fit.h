#pragma once
// Circle fits in the plane (METHOD.md 2, step 3), the ones researchers compare:
//   kasa:      algebraic, minimises sum (x^2 + y^2 + D x + E y + F)^2 (Kasa 1976). One linear solve, but
//              biased toward small circles on short arcs, badly so at the seed's 40 deg.
//   pratt:     algebraic with Pratt's normalisation B^2 + C^2 - 4 A D = 1 (Pratt 1987), solved as
//              Chernov's SVD-based generalised eigenproblem.
//   taubin:    algebraic with Taubin's normalisation (Taubin 1991), Chernov's SVD form. Nearly
//              unbiased on short arcs and the usual starting point of geometric fits.
//   geometric: orthogonal-distance least squares, minimises sum (|p_k - c| - R)^2 by
//              Levenberg-Marquardt on (c, R), started from the Taubin fit. The maximum-likelihood fit
//              for isotropic Gaussian noise.
// All fits work on centred, scaled copies of the points, so their conditioning does not depend on where
// the arc lies or on the unit of length. Every fit is exact for points exactly on a circle.
// The default of the geometric estimator is chosen by evidence (tests/estimators/geometric and
// bench/geometric_accuracy.cc): see GeometricEstimator::Options::circle_fit.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace kincal::geometric {

enum class CircleFitMethod { kKasa, kPratt, kTaubin, kGeometric };
std::string ToString(CircleFitMethod method);
// "kasa", "pratt", "taubin", "geometric"; throws std::invalid_argument naming the choices.
CircleFitMethod ParseCircleFitMethod(const std::string& name);
std::vector<std::string> CircleFitMethodNames();

struct CircleFit2d {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.0;
  int iterations = 0;     // Levenberg-Marquardt iterations (geometric fit only)
  bool converged = true;  // false if the geometric fit hit its iteration limit
};

// Each needs at least 3 points not all on one line; throws std::invalid_argument otherwise.
CircleFit2d FitCircleKasa(const std::vector<Eigen::Vector2d>& points);
CircleFit2d FitCirclePratt(const std::vector<Eigen::Vector2d>& points);
CircleFit2d FitCircleTaubin(const std::vector<Eigen::Vector2d>& points);
// Orthogonal-distance fit from `initial` (e.g. a Taubin fit); iterates until the step is at rounding
// level, so that its result is a smooth function of the points (the estimator differentiates it
// numerically to propagate the noise).
CircleFit2d FitCircleGeometric(const std::vector<Eigen::Vector2d>& points, const CircleFit2d& initial,
                               int max_iterations = 100);
CircleFit2d FitCircle(const std::vector<Eigen::Vector2d>& points, CircleFitMethod method, int max_iterations = 100);

}  // namespace kincal::geometric
