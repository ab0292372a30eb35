#pragma once
// The steps every error-model estimator shares (least_squares, ceres, nlopt, ipopt), so that they differ
// only in how they minimise:
//   1. PrepareErrorModel: place the bases, the tool and the markers in closed form (start_placement.h),
//      so that every estimator starts from the same point and bounds are centred on it; build the problem,
//      analyse identifiability at the start (identifiability.h) and hold what the data cannot determine.
//   2. the estimator minimises sum_i w_i rho(|r_i(x)|^2) over x, from problem->InitialX(); then
//      ReanalyzeIdentifiability at the solution and, when it frees parameters, minimises again.
//   3. FinishErrorModel: write x into the identified robot; covariance sigma^2 (J^T W J)^-1 with
//      sigma^2 = sum w rho' |r|^2 / (m - p) (m residuals, p free parameters; the Cramer-Rao bound for
//      Gaussian noise when the weights are the inverse variances); fill the report: every parameter with
//      its start value, value, standard deviation and note, the held parameters, the condition number
//      and observability indices, the residual RMS.
// Example (an estimator's DoEstimate):
//   PreparedErrorModel prep = PrepareErrorModel(start, controller, data, options_.error_model, weighting);
//   Eigen::VectorXd x = prep.problem->InitialX();
//   ... minimise ...
//   if (ReanalyzeIdentifiability(x, weighting, &prep, &x)) { ... minimise again ... }
//   report->status = ...; report->iterations = ...; report->message = ...;
//   FinishErrorModel(prep, x, weighting, identified, report);
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/identifiability.h"
#include "estimators/error_model/normal_equations.h"
#include "estimators/error_model/weak_parameters.h"
#include "estimators/estimator.h"

namespace kincal {

struct PreparedErrorModel {
  Robot input;                                 // the start robot as given (markers the data name but it
                                               // lacks added at the tool origin)
  Robot start;                                 // the same with bases, tool and markers placed
  std::vector<std::string> placed;             // what the placement set (StartPlacement::placed)
  std::unique_ptr<ErrorModelProblem> problem;  // identifiable parameters free
  IdentifiabilityAnalysis identifiability;     // at the start, of the problem before holding
  NormalEquations initial;                     // of `problem` at its InitialX(), with the weighting given
  double registered_rms = NAN;                 // position RMS of the start once placed, m
  std::vector<std::string> warnings;
  // What the placement fell back on but the fit normally recovers from (markers placed from the robot
  // file's positions first): details.placement_notes, and warnings only when the fit did not converge.
  std::vector<std::string> placement_notes;
  // Weakly identifiable parameters (weak_parameters.h) found at the first solution, and those of them
  // held because they have no prior (name, reason), kept when the problem is rebuilt.
  std::vector<WeakParameter> weak;
  std::vector<std::pair<std::string, std::string>> weak_held;
  // The normal equations of `problem` (with its priors) at one x and weighting, where a minimiser left
  // them: the analyses at that point read them (NormalEquationsAt) instead of passing over the data again.
  // Shared by copies; a rebuilt prep starts without.
  struct Evaluated {
    Eigen::VectorXd x;
    std::vector<double> weights;
    RobustLoss loss;
    NormalEquations ne;
  };
  std::shared_ptr<const Evaluated> evaluated;
};

// AccumulateNormalEquations(*prep.problem, x, weighting, what, with_prior), or the same to the bit from
// prep.evaluated when it holds that x and weighting (then with J^T r and J^T J whatever `what` asks).
NormalEquations NormalEquationsAt(const PreparedErrorModel& prep, const Eigen::VectorXd& x,
                                  const RowWeighting& weighting, Accumulate what = Accumulate::kNormalEquations,
                                  bool with_prior = true);
// Keeps `ne` (AccumulateNormalEquations(*prep->problem, x, weighting) with the priors) in prep->evaluated.
void KeepNormalEquations(const Eigen::VectorXd& x, const RowWeighting& weighting, NormalEquations ne,
                         PreparedErrorModel* prep);

// Throws std::invalid_argument for bad input (ErrorModelProblem's conditions).
PreparedErrorModel PrepareErrorModel(const Robot& start, const Robot& controller, const Dataset& data,
                                     const ErrorModelOptions& options, const RowWeighting& weighting = RowWeighting());

// Re-analyses identifiability at `solution` (a minimiser of prep->problem). A start value can hide what
// the data determine: a marker that starts on the last joint's axis makes that row's alpha and a look
// redundant with the tool. When the identifiable set at the solution differs, prep is rebuilt from the
// solution (prep->start becomes the solution robot), *x is its new InitialX() and the result is true: the
// estimator minimises again. Otherwise *x = solution and the result is false. Costs one pass.
bool ReanalyzeIdentifiability(const Eigen::VectorXd& solution, const RowWeighting& weighting, PreparedErrorModel* prep,
                              Eigen::VectorXd* x);

// Rebuilds prep at `solution` (prep->start becomes the solution robot; identifiability re-analysed, weak
// holds and prior means kept) with the priors weighed by `prior_noise` (m); *x = its InitialX().
void RestartAt(const Eigen::VectorXd& solution, const RowWeighting& weighting, double prior_noise,
               PreparedErrorModel* prep, Eigen::VectorXd* x);
// The same for a restart that changes only the prior noise, under ReanalyzeIdentifiability's rule: a
// re-analysis that would hand the link geometry to joint-level terms is refused, prep keeps its analysis
// (with the new noise) and *x = solution.
void RestartWithPriorNoise(const Eigen::VectorXd& solution, const RowWeighting& weighting, double prior_noise,
                           PreparedErrorModel* prep, Eigen::VectorXd* x);

// What a re-analysis of identifiability at a solution changes against the analysis in force (the
// unidentifiable names before and after; `candidates` give each name's group): the names it frees and
// holds (" name" each).
struct IdentifiabilityChange {
  std::string freed, held;
  bool frees_joint_level = false;  // frees a joint-level (joint error) coefficient
  bool holds_geometry = false;     // holds a link (joint) parameter
  // Joint-level terms are corrections to a geometry the data determine: a solution where they would take
  // over what the link geometry did (the joint errors rank first in the analysis, so the geometry is what
  // it holds) has run off along the terms' near-null directions, not found new information. Such a change
  // is refused, at the first solution and at every prior-noise restart.
  bool HandsGeometryToJointLevel() const { return frees_joint_level && holds_geometry; }
};
IdentifiabilityChange CompareIdentifiability(const std::vector<ErrorModelParameter>& candidates,
                                             const std::vector<std::string>& before,
                                             const std::vector<std::string>& after);

// How the free parameters restart when weak ones are held: where the fit left them, or moved with the held
// ones along the cost's valley (to where the quadratic model at the solution is least with the held ones
// fixed).
enum class HoldRestart { kFreeStay, kFreeFollowValley };

// At a solution of prep->problem: finds the weakly identifiable parameters (prep->weak) and holds those
// without a prior (prep->weak_held) at their start values, the free parameters restarting as `restart`
// says; when it holds any, rebuilds prep there (RestartAt) and returns true: the estimator minimises again
// from *x. Otherwise *x = solution.
bool HoldWeakParameters(const Eigen::VectorXd& solution, const RowWeighting& weighting, HoldRestart restart,
                        PreparedErrorModel* prep, Eigen::VectorXd* x);

// At a point where the fit stopped without converging: adds to prep->weak the parameters the data
// determine worse than their reference there (FindWeakParameters), held or not, so that none goes unnamed.
void NameWeakParameters(const Eigen::VectorXd& x, const RowWeighting& weighting, PreparedErrorModel* prep);

// The noise standard deviation per residual at x: sqrt(sum w rho' |r|^2 / (m - p)) of the data alone.
double DataSigma(const NormalEquations& ne, int num_parameters);

// Whether x is within a small fraction of a standard deviation of the minimum: the Gauss-Newton
// decrease of the cost predicted at x, g^T N^-1 g, is at most (0.1 sigma)^2, i.e. the remaining step is
// below 0.1 standard deviations in the metric of the parameters' covariance (N/sigma^2). A flat valley
// where a solver ran out of iterations while moving along poorly determined directions passes.
bool WithinNoiseOfMinimum(const NormalEquations& ne, double sigma);

// The Gauss-Newton decrease of the cost predicted at the point of `ne`, g^T N^-1 g (g = J^T W r, N = J^T W J
// with the priors), in the cost's units (m^2); NaN where N is not positive definite.
double PredictedDecrease(const NormalEquations& ne);

// Whether a run that used its budget stopped in a flat valley: what Gauss-Newton predicts is left is at
// most 1 % of the cost, so the fit is at the bottom in every direction but its poorly determined ones.
// There the weak analysis (HoldWeakParameters) names them, as at a converged solution.
bool InFlatValley(const NormalEquations& ne);

struct Covariance {
  Eigen::MatrixXd matrix;  // p x p, sigma^2 (J^T W J)^-1, x's units
  Eigen::VectorXd stddev;  // sqrt of the diagonal (NaN where J^T W J is singular)
  double sigma = 0.0;      // estimated noise standard deviation per residual, m
  int degrees_of_freedom = 0;
};
// From the normal equations at the solution (NormalEquations of AccumulateNormalEquations).
Covariance ComputeCovariance(const NormalEquations& at_solution, int num_parameters);

// Writes the identified robot and fills the report's common fields (see above). Does not set status,
// message or iterations.
void FinishErrorModel(const PreparedErrorModel& prepared, const Eigen::VectorXd& x, const RowWeighting& weighting,
                      Robot* identified, EstimationReport* report);
// The same when the caller already has the normal equations at x (saves one pass over the data).
void FinishErrorModel(const PreparedErrorModel& prepared, const Eigen::VectorXd& x, const NormalEquations& at_x,
                      Robot* identified, EstimationReport* report);

// When every parameter is held (nothing to solve), finishes the report as converged after zero
// iterations and returns true; otherwise returns false and leaves everything untouched.
bool FinishIfNothingFree(const PreparedErrorModel& prepared, Robot* identified, EstimationReport* report);

}  // namespace kincal
