#pragma once
// Weakly identifiable parameters: those the data determine worse than their prior says they are known
// (or, without a prior, worse than the default prior of their kind, PriorOptions): the standard
// deviation from the data alone, sigma sqrt([(J^T W J)^-1]_jj), above ErrorModelParameter::reference_sd.
// Unlike the identifiability analysis (identifiability.h), which holds exactly redundant columns, these
// columns are independent but nearly so: the fit can move them far along a flat valley of the cost.
// The combination each one trades against is read from the eigenvector of the column-normalised J^T W J
// that carries most of its variance: the other parameters with the largest components there.
// Without a prior a weak parameter is held at its start value (HoldWeakParameters, error_model.h), one at a
// time, the weakest (largest sd / reference) first, since holding one often determines the others.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimators/error_model/error_model_problem.h"

namespace kincal {

struct WeakParameter {
  std::string name;
  double data_sd = 0.0;       // from the data alone, x's units (infinite: not determined at all)
  double reference_sd = 0.0;  // prior sd, or the default of its kind, x's units
  bool has_prior = false;
  bool held = false;                        // held at its start value because it has no prior
  std::vector<std::string> trades_against;  // 1-4 names
  std::string Describe() const;             // "alpha_5 (data sd 3.1e-02 against 2.0e-03; trades against a_5, d_5)"
};

// Standard deviations from the data alone of the parameters `subset` (indices into problem.parameters();
// empty: all) from the data's J^T W J (no prior) and the noise sigma. Infinite where the data do not
// determine a combination. When `trades` is not null, fills per parameter (same order) the names of the
// parameters it trades against.
Eigen::VectorXd DataStddev(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data, double sigma,
                           const std::vector<int>& subset, std::vector<std::vector<std::string>>* trades = nullptr);

// The weak parameters among `subset` (empty: all free), in parameter order.
std::vector<WeakParameter> FindWeakParameters(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data,
                                              double sigma, const std::vector<int>& subset = {});

// The parameters without a prior to hold, greedily: while some are weak, the one with the largest
// data_sd / reference_sd is removed and the rest re-analysed (indices into problem.parameters()).
// *weak receives the weak parameters of the first analysis that are held or have a prior (held ones marked).
std::vector<int> ChooseWeakToHold(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ_data, double sigma,
                                  std::vector<WeakParameter>* weak);

}  // namespace kincal
