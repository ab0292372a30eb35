// The measurement plan (planning/plan.h).
#include "planning/plan.h"

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "framework/error.h"
#include "framework/random.h"
#include "framework/units.h"
#include "planning/constraints.h"
#include "planning/tour.h"
#include "programs/program.h"

namespace kincal {
namespace {

// The column of joint j (0-based) and its unit's factor to SI, from the header's q<j+1>_<unit>.
int JointColumn(const CsvTable& table, const Robot& robot, int j, double* to_si, const std::string& source) {
  const bool prismatic = robot.model().joint_type(j) == JointType::kPrismatic;
  const std::vector<std::pair<std::string, double>> units =
      prismatic ? std::vector<std::pair<std::string, double>>{{"mm", 1e-3}, {"m", 1.0}}
                : std::vector<std::pair<std::string, double>>{{"deg", kDegree}, {"rad", 1.0}};
  for (const auto& [unit, factor] : units) {
    const int column = FindColumn(table, "q" + std::to_string(j + 1) + "_" + unit);
    if (column >= 0) {
      *to_si = factor;
      return column;
    }
  }
  ThrowInputError(source, table.header.line, 1,
                  "expected a column q" + std::to_string(j + 1) + (prismatic ? "_mm or _m" : "_deg or _rad") +
                      " (the robot has " + std::to_string(robot.dof()) + " joints)");
}

double ParseCell(const CsvRow& row, int column, const std::string& source) {
  const std::string& text = row.cells[column];
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
    ThrowInputError(source, row.line, row.columns[column], "expected a finite number, got '" + text + "'");
  }
  return value;
}

std::string ReasonKind(const std::string& why) { return why.substr(0, why.find(':')); }

// The robot whose parameters the design is for (PlanOptions::design_model): the nominal, or the nominal
// with gravity and harmonic terms on every revolute joint that has none of that type.
Robot DesignRobot(const Robot& nominal, const PlanOptions& options) {
  if (options.design_model == "geometry") return nominal;
  Robot design = nominal;
  using Type = JointErrorTerm::Type;
  const auto has = [&](int joint, Type type) {
    for (const JointErrorTerm& t : nominal.joint_errors.terms) {
      if (t.joint == joint && t.type == type) return true;
    }
    return false;
  };
  for (Type type : {Type::kGravity, Type::kHarmonic}) {
    for (int j = 0; j < nominal.dof(); ++j) {
      if (nominal.model().joint_type(j) != JointType::kRevolute || has(j, type)) continue;
      JointErrorTerm term;
      term.type = type;
      term.joint = j;
      if (type == Type::kHarmonic) term.orders = {1, 2};
      design.joint_errors.terms.push_back(term);
    }
  }
  design.joint_errors.Bind(design.model());
  return design;
}

}  // namespace

CandidatePool ParseCandidatePool(const std::string& text, const std::string& source, const Robot& robot) {
  CandidatePool pool;
  pool.source = source;
  pool.table = ParseCsv(text, source);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) pool.lines.push_back(line);
  const int n = robot.dof();
  std::vector<int> columns(n);
  std::vector<double> to_si(n);
  for (int j = 0; j < n; ++j) columns[j] = JointColumn(pool.table, robot, j, &to_si[j], source);
  if (pool.table.rows.empty()) ThrowInputError(source, pool.table.header.line, 1, "no candidate rows");
  for (const CsvRow& row : pool.table.rows) {
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) q[j] = ParseCell(row, columns[j], source) * to_si[j];
    pool.q.push_back(q);
  }
  return pool;
}

CandidatePool GenerateCandidates(const Robot& robot, const PlanOptions& options) {
  const int n = robot.dof();
  std::string text = "# kincal plan: " + std::to_string(options.generated_candidates) +
                     " configurations drawn within the joint limits, seed " + std::to_string(options.seed) + "\n";
  std::vector<double> unit(n);
  for (int j = 0; j < n; ++j) {
    const bool prismatic = robot.model().joint_type(j) == JointType::kPrismatic;
    unit[j] = prismatic ? robot.length_unit.to_si : robot.angle_unit.to_si;
    text += (j ? ",q" : "q") + std::to_string(j + 1) + "_" + (prismatic ? robot.length_unit.name : robot.angle_unit.name);
  }
  text += "\n";
  Rng rng(static_cast<uint64_t>(options.seed));
  for (int i = 0; i < options.generated_candidates; ++i) {
    for (int j = 0; j < n; ++j) {
      const auto [lo, hi] = robot.Limit(j);
      const double margin = robot.model().joint_type(j) == JointType::kRevolute ? options.joint_limit_margin : 0.0;
      const double value = lo + margin < hi - margin ? rng.Uniform(lo + margin, hi - margin) : 0.5 * (lo + hi);
      text += (j ? "," : "") + FormatNumber(value / unit[j]);
    }
    text += "\n";
  }
  return ParseCandidatePool(text, "generated candidates", robot);
}

std::string PoolRowsCsv(const CandidatePool& pool, const std::vector<int>& rows) {
  std::string out;
  for (int l = 0; l < pool.table.header.line; ++l) out += pool.lines[l] + "\n";
  for (int i : rows) out += pool.lines[pool.table.rows[i].line - 1] + "\n";
  return out;
}

PlanningProblem PreparePlanning(const Robot& nominal, const CandidatePool& pool, const PlanOptions& options,
                                int at_least) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("plan options: " + why);
  const PoseConstraints constraints(nominal, options);
  PlanningProblem problem;
  std::vector<Eigen::VectorXd> feasible, workspace;
  for (size_t i = 0; i < pool.q.size(); ++i) {
    const std::string violation = constraints.Violation(pool.q[i]);
    if (violation.empty()) {
      problem.feasible.push_back(static_cast<int>(i));
      feasible.push_back(pool.q[i]);
    } else {
      ++problem.rejected[ReasonKind(violation)];
    }
    if (options.workspace_samples == 0 && constraints.ArmViolation(pool.q[i]).empty()) workspace.push_back(pool.q[i]);
  }
  if (static_cast<int>(feasible.size()) < at_least) {
    std::string reasons;
    for (const auto& [kind, count] : problem.rejected) reasons += (reasons.empty() ? "" : ", ") + kind + " " + std::to_string(count);
    throw std::invalid_argument("plan: " + std::to_string(at_least) + " poses asked for, " +
                                std::to_string(feasible.size()) + " of " + std::to_string(pool.q.size()) +
                                " candidates meet the constraints (rejected: " + reasons + ")");
  }
  Robot design = DesignRobot(nominal, options);
  try {
    problem.model = BuildInformation(design, feasible, options.measurement_noise);
  } catch (const std::invalid_argument&) {
    // Too few candidates for the potential terms (3 residuals each): design for the file's parameters,
    // whose own errors then surface from BuildInformation.
    design = nominal;
    problem.model = BuildInformation(design, feasible, options.measurement_noise);
  }
  if (options.criterion == "I") {
    if (options.workspace_samples > 0) {
      PlanOptions drawn = options;
      drawn.generated_candidates = options.workspace_samples;
      drawn.seed = options.seed + 1;
      for (const Eigen::VectorXd& q : GenerateCandidates(nominal, drawn).q) {
        if (constraints.ArmViolation(q).empty()) workspace.push_back(q);
      }
    }
    if (workspace.empty()) throw std::invalid_argument("plan: no configuration of the workspace sample meets the arm's constraints");
    problem.workspace = WorkspaceRows(design, workspace, options.measurement_noise, problem.model);
  }
  return problem;
}

MeasurementPlan PlanMeasurements(const Robot& nominal, const CandidatePool& pool, int K, const PlanOptions& options) {
  if (K < 1) throw std::invalid_argument("plan: --poses must be at least 1, got " + std::to_string(K));
  const PlanningProblem problem = PreparePlanning(nominal, pool, options, K);
  MeasurementPlan plan;
  plan.feasible = problem.feasible;
  plan.rejected = problem.rejected;
  plan.parameters = problem.model.names;
  std::vector<int> all(problem.feasible.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  const std::vector<int> picked = GreedySelect(problem.model, all, K, options.criterion, problem.workspace);
  for (int k : picked) plan.chosen.push_back(problem.feasible[k]);
  plan.scores = ScoreDesign(problem.model, picked, problem.workspace);
  std::vector<Eigen::VectorXd> q;
  for (int i : plan.chosen) q.push_back(pool.q[i]);
  const std::vector<int> order = OrderPoses(nominal, q);
  for (int k : order) plan.rows.push_back(plan.chosen[k]);
  std::vector<int> identity(q.size());
  for (size_t k = 0; k < identity.size(); ++k) identity[k] = static_cast<int>(k);
  plan.travel_time = PathTime(nominal, q, order);
  plan.chosen_order_time = PathTime(nominal, q, identity);
  return plan;
}

}  // namespace kincal
