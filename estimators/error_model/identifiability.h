#pragma once
// Identifiability of the error model's parameters from a dataset, before anything is solved.
//
// Scaling. Each column of the identification Jacobian J is divided by its norm (Hollerbach & Wampler,
// "The calibration index and taxonomy for robot kinematic calibration methods", IJRR 15(6), 1996):
// S = D J^T J D with D = diag(1 / |J_j|), so that units and lever arms do not decide.
//
// Choice of the parameters to hold. A rank-revealing factorisation with column selection on the scaled
// Jacobian, computed through S (right-looking Cholesky of S with a fixed, documented column order:
// base, session bases, markers, tool, ratios, then the joints' rows in order): a column is kept when the
// sine of its angle to the span of the columns kept before it exceeds `tolerance` (its Schur
// complement in S is the squared sine), else it is held at its start value as not identifiable. This is
// QR with column selection (the R factor of J D restricted to the kept columns is the Cholesky factor of
// S), with the selection order fixed instead of pivoted on norms, so that the classic redundancies
// resolve the way calibration texts do: the first row of a chain against the base (a 6-DOF base
// absorbs it), the last joint's offset and d against the tool, d_i against d_(i+1) on parallel axes.
// Deterministic: the same data always holds the same parameters. Memory O(p^2) (no J needed).
// A column with (numerically) no effect, |J_j| * scale_j <= 1e-3 tolerance * max_k |J_k| * scale_k
// (scale: the a priori CharacteristicScales), is held as "no effect on the measurements".
//
// Observability indices of the identifiable columns, with J scaled by the a priori characteristic
// scales (J_c = J diag(scale): the marker displacement caused by a typical error of each parameter), and
// singular values s_1 >= ... >= s_L of J_c, m = number of rows (poses x markers). As numbered by Sun &
// Hollerbach, "Observability index selection for robot calibration", ICRA 2008:
//   O1 = (s_1 s_2 ... s_L)^(1/L) / sqrt(m)   Borm & Menq 1991: the volume of the error ellipsoid
//   O2 = s_L / s_1                           Driels & Pathre 1990: inverse condition number
//   O3 = s_L                                 Nahvi, Hollerbach & Hayward 1994: minimum singular value
//   O4 = s_L^2 / s_1                         Nahvi & Hollerbach 1996: noise amplification index
//   O5 = 1 / (1/s_1 + ... + 1/s_L)           Sun & Hollerbach 2008: inverse of the sum of the
//                                            parameter standard deviations' bound (A-optimality-like)
// All but O2 are in metres (the unit of J_c); larger is better for every index.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimators/error_model/error_model_problem.h"

namespace kincal {

struct ObservabilityIndices {
  double o1 = 0.0, o2 = 0.0, o3 = 0.0, o4 = 0.0, o5 = 0.0;
};

struct IdentifiabilityAnalysis {
  std::vector<int> identifiable;  // indices into the analysed problem's x
  std::vector<int> unidentifiable;
  std::vector<std::string> unidentifiable_names;
  // Per unidentifiable parameter: "no effect on the measurements", or "redundant with" the kept parameters
  // that carry most of its column (largest least-squares coefficients in the scaled basis).
  std::vector<std::string> reasons;
  int rank = 0;
  double condition_number = 0.0;                   // of the column-normalised J, identifiable columns
  Eigen::VectorXd singular_values;                 // same matrix, descending
  Eigen::VectorXd characteristic_singular_values;  // of J_c, descending
  ObservabilityIndices observability;
};

// JtJ: J^T J of `problem` at some x (AccumulateNormalEquations). num_rows: m in O1.
IdentifiabilityAnalysis AnalyzeIdentifiability(const ErrorModelProblem& problem, const Eigen::MatrixXd& JtJ,
                                               int num_rows, double tolerance);

// The indices above from the singular values of J_c (descending) and the number of rows.
ObservabilityIndices ComputeObservabilityIndices(const Eigen::VectorXd& singular_values, int num_rows);

}  // namespace kincal
