#pragma once
// Planning the measurement poses of a calibration (`kincal plan`): from candidates (the rows of a pool
// file, every column kept as written, or configurations drawn within the joint limits), those that meet
// the constraints (planning/constraints.h), K of them chosen by an optimality criterion on the
// identifiable parameters with their priors (planning/selection.h), in the order that shortens the
// travel between them (planning/tour.h).
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/csv.h"
#include "planning/plan_options.h"
#include "planning/selection.h"
#include "robot/robot.h"

namespace kincal {

struct CandidatePool {
  std::string source;
  CsvTable table;                  // as read (or generated): comments, header and rows, cells verbatim
  std::vector<std::string> lines;  // the text's lines, written back as they are
  std::vector<Eigen::VectorXd> q;  // per row, the joint columns in rad (m for prismatic joints)
};

// The rows of a pool file: joint columns q1_deg..qN_deg or q1_rad..qN_rad (q1_mm/q1_m for prismatic
// joints), any other columns kept. Throws std::invalid_argument "source:line:column: what".
CandidatePool ParseCandidatePool(const std::string& text, const std::string& source, const Robot& robot);
// options.generated_candidates configurations drawn uniformly within the limits less the margin
// (seeded), in the robot file's angle unit, each value written as the shortest text that reads back.
CandidatePool GenerateCandidates(const Robot& robot, const PlanOptions& options);
// The pool's lines up to its header (comments included), then the lines of `rows` (indices into the
// pool) in that order, each as written: a CSV text.
std::string PoolRowsCsv(const CandidatePool& pool, const std::vector<int>& rows);

struct MeasurementPlan {
  std::vector<int> rows;    // indices into the pool, in the planned (travel) order
  std::vector<int> chosen;  // the same, in the order the criterion chose them
  std::vector<int> feasible;                   // the candidates that meet the constraints
  std::map<std::string, int> rejected;         // kind of constraint broken (the first) -> candidates
  std::vector<std::string> parameters;         // the identifiable parameters the criterion weighs
  DesignScores scores;                         // of the chosen poses
  double travel_time = 0.0;                    // s (or rad at 1 rad/s): planned order
  double chosen_order_time = 0.0;              // the same in the order chosen
};

// Throws std::invalid_argument for invalid options, K < 1 or fewer feasible candidates than K.
MeasurementPlan PlanMeasurements(const Robot& nominal, const CandidatePool& pool, int K, const PlanOptions& options);

// The part of the plan before the choice, for studies of the criteria.
struct PlanningProblem {
  std::vector<int> feasible;               // the candidates meeting the constraints (pool indices)
  std::map<std::string, int> rejected;
  InformationModel model;                  // rows: the feasible candidates, in that order
  std::vector<Eigen::MatrixXd> workspace;  // I-optimality's rows: where the arm works (ArmViolation "")
};
// Throws std::invalid_argument for invalid options or fewer than `at_least` feasible candidates.
PlanningProblem PreparePlanning(const Robot& nominal, const CandidatePool& pool, const PlanOptions& options,
                                int at_least = 1);

}  // namespace kincal
