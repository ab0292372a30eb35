#pragma once
// Choosing K measurement poses from candidates by an optimality criterion on the identifiable
// parameters with their priors.
//
// The information of the fit kincal runs (estimators/error_model: positions, Gaussian priors by kind,
// PriorOptions' defaults) at the nominal robot: parameters held as not identifiable from the whole
// candidate set (identifiability.h) are left out; the rest are scaled by their characteristic scales
// (ErrorModelProblem::CharacteristicScales), so that M = sum_i J_i^T J_i + P, J_i the 3 x p position
// Jacobian of candidate i and P the priors' information, both in units of the measurement noise's
// variance (a parameter without a prior, the base's, gets one 1000 characteristic scales wide, which
// only keeps M invertible until the poses determine it). Criteria, on C = M^-1:
//   D  maximise log det M           (the volume of the parameters' confidence ellipsoid)
//   A  minimise trace C             (the sum of the parameters' variances, scaled)
//   I  minimise trace(W C), W the mean of J_s^T J_s over a sample of the workspace: the mean variance
//      of a predicted position where the arm will work (Atkinson, Donev & Tobias, Optimum Experimental
//      Designs, 2007, 10.6); the sample: the candidates that meet the arm's own constraints, tracker or
//      not (or PlanOptions::workspace_samples configurations drawn within the limits)
// Greedy forward selection: each step adds the candidate that improves the criterion most, from the
// Woodbury identity (a rank-3 update per candidate: S = I + J C J^T; D gains log det S, A gains
// trace(S^-1 J C C J^T), I gains trace(S^-1 J C W C J^T)), then updates C by it. This is the forward
// half of Fedorov's exchange and Mitchell's DETMAX (Technometrics 16(2), 1974), which figaroh's
// optimal/base_optimal_calibration.py runs in full (its Detmax class, beside an SOCP relaxation) for its
// D-optimal choice from a user's pool. The exchange half is left out on purpose: it improves each
// criterion's own value but predicted held-out poses of a real arm worse (docs/planning.md).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot/robot.h"

namespace kincal {

struct InformationModel {
  std::vector<std::string> names;        // the identifiable parameters
  std::vector<Eigen::MatrixXd> rows;     // per configuration, 3 x p scaled Jacobian over the noise
  Eigen::MatrixXd prior;                 // p x p, scaled, over the noise's variance
};

// The model of `robot` at configurations q (rad), the identifiable set judged over all of them.
// noise: m per coordinate. Throws std::invalid_argument when no parameter is identifiable.
InformationModel BuildInformation(const Robot& robot, const std::vector<Eigen::VectorXd>& q, double noise);
// The scaled Jacobians of `robot` at q for the parameters of `model` (same names, same scaling).
std::vector<Eigen::MatrixXd> WorkspaceRows(const Robot& robot, const std::vector<Eigen::VectorXd>& q, double noise,
                                           const InformationModel& model);

// K indices into model.rows among `allowed` (indices), in the order chosen. criterion: "D", "A" or "I";
// workspace: I's rows (ignored otherwise). Throws std::invalid_argument when K exceeds allowed.size().
std::vector<int> GreedySelect(const InformationModel& model, const std::vector<int>& allowed, int K,
                              const std::string& criterion, const std::vector<Eigen::MatrixXd>& workspace);

// The criteria of a chosen set (for reports and tests): log det M, trace C, trace(W C).
struct DesignScores {
  double log_det = 0.0, trace_c = 0.0, trace_wc = 0.0;
};
DesignScores ScoreDesign(const InformationModel& model, const std::vector<int>& chosen,
                         const std::vector<Eigen::MatrixXd>& workspace);

}  // namespace kincal
