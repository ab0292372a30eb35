#pragma once
// Gaussian priors as factors (PriorOptions in error_model_problem.h): one residual per free parameter j
// with a prior, r_j = s_j (x_j - mu_j), s_j = noise / sd_j (noise: the problem's prior_noise(), m per
// residual), so that sum r_j^2 is noise^2 times the prior's negative log density. The one list every
// backend reads: the normal equations (AddPriorTerms, PriorInformation), Ceres (one residual block per
// parameter block) and, through the normal equations, NLopt and Ipopt. Empty while prior_noise() is 0.
#include <vector>

#include <Eigen/Core>

#include "estimators/error_model/error_model_problem.h"

namespace kincal {

struct PriorFactor {
  int index = 0;       // into x
  double mean = 0.0;   // mu_j, x's units
  double scale = 0.0;  // s_j = noise / sd_j, m per unit of x
  double Residual(const Eigen::VectorXd& x) const { return scale * (x[index] - mean); }
};

std::vector<PriorFactor> PriorFactors(const ErrorModelProblem& problem);

}  // namespace kincal
