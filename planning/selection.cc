// Greedy optimal design of measurement poses (planning/selection.h).
#include "planning/selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/identifiability.h"
#include "estimators/error_model/normal_equations.h"
#include "framework/dataset.h"

namespace kincal {
namespace {

// A dataset of the configurations, measured where the robot puts its marker (the Jacobian at the
// nominal parameters does not depend on the measured values).
Dataset NominalData(const Robot& robot, const std::vector<Eigen::VectorXd>& q) {
  Dataset data;
  data.dof = robot.dof();
  data.source = "candidates";
  for (const Eigen::VectorXd& qi : q) {
    Measurement m;
    m.q = qi;
    m.p = robot.model().ForwardKinematics(qi) * robot.MarkerPosition("");
    data.rows.push_back(m);
  }
  return data;
}

ErrorModelOptions PriorsOn() {
  ErrorModelOptions options;
  options.prior.enabled = true;
  options.prior.given = true;
  return options;
}

// Position rows of `problem` at its start, scaled by `scale`, over `noise`.
std::vector<Eigen::MatrixXd> ScaledRows(const ErrorModelProblem& problem, const Eigen::VectorXd& scale, double noise) {
  const Eigen::VectorXd x = problem.InitialX();
  auto ws = problem.NewWorkspace();
  Vector6d r;
  Matrix6Xd J;
  std::vector<Eigen::MatrixXd> rows;
  for (int i = 0; i < problem.num_rows(); ++i) {
    problem.EvaluateRow(i, x, ws.get(), &r, &J);
    rows.push_back(J.topRows(3) * scale.asDiagonal() / noise);
  }
  return rows;
}

// The identifiable problem over the configurations (held: what the whole set cannot determine).
ErrorModelProblem IdentifiableProblem(const Robot& robot, const Dataset& data, double noise) {
  const ErrorModelOptions options = PriorsOn();
  ErrorModelProblem problem(robot, robot, data, options);
  const NormalEquations ne =
      AccumulateNormalEquations(problem, problem.InitialX(), RowWeighting(), Accumulate::kNormalEquations, false);
  const IdentifiabilityAnalysis a =
      AnalyzeIdentifiability(problem, ne.JtJ, problem.num_rows(), options.identifiability_tolerance);
  if (a.identifiable.empty()) throw std::invalid_argument("plan: no parameter is identifiable from the candidates");
  ErrorModelProblem held = a.unidentifiable.empty() ? problem : problem.Hold(a.unidentifiable, "not identifiable", true);
  held.set_prior_noise(noise);
  return held;
}

double Gain(const std::string& criterion, const Eigen::MatrixXd& G, const Eigen::MatrixXd& J,
            const Eigen::MatrixXd& W) {
  const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(J.rows(), J.rows()) + G * J.transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (criterion == "D") return 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  if (criterion == "A") return (llt.solve(G) * G.transpose()).trace();
  return (llt.solve(G) * W * G.transpose()).trace();
}

Eigen::MatrixXd MeanGram(const std::vector<Eigen::MatrixXd>& rows, int p) {
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(p, p);
  for (const Eigen::MatrixXd& J : rows) W.noalias() += J.transpose() * J;
  return rows.empty() ? W : W / static_cast<double>(rows.size());
}

}  // namespace

InformationModel BuildInformation(const Robot& robot, const std::vector<Eigen::VectorXd>& q, double noise) {
  const Dataset data = NominalData(robot, q);
  const ErrorModelProblem problem = IdentifiableProblem(robot, data, noise);
  const Eigen::VectorXd scale = problem.CharacteristicScales();
  InformationModel model;
  model.names = problem.ParameterNames();
  model.rows = ScaledRows(problem, scale, noise);
  const Eigen::VectorXd prior = PriorInformation(problem);  // (noise / sd)^2, unscaled
  const int p = problem.num_parameters();
  model.prior = Eigen::MatrixXd::Zero(p, p);
  for (int j = 0; j < p; ++j) {
    // Over noise^2 and scaled: (scale / sd)^2; without a prior, sd = 1000 scales.
    model.prior(j, j) = prior[j] > 0.0 ? prior[j] * scale[j] * scale[j] / (noise * noise) : 1e-6;
  }
  return model;
}

std::vector<Eigen::MatrixXd> WorkspaceRows(const Robot& robot, const std::vector<Eigen::VectorXd>& q, double noise,
                                           const InformationModel& model) {
  const Dataset data = NominalData(robot, q);
  ErrorModelProblem problem(robot, robot, data, PriorsOn());
  std::vector<int> hold;
  const std::vector<std::string> names = problem.ParameterNames();
  for (int j = 0; j < static_cast<int>(names.size()); ++j) {
    if (std::find(model.names.begin(), model.names.end(), names[j]) == model.names.end()) hold.push_back(j);
  }
  if (!hold.empty()) problem = problem.Hold(hold, "not identifiable", true);
  if (problem.ParameterNames() != model.names) throw std::logic_error("plan: workspace parameters differ");
  return ScaledRows(problem, problem.CharacteristicScales(), noise);
}

std::vector<int> GreedySelect(const InformationModel& model, const std::vector<int>& allowed, int K,
                              const std::string& criterion, const std::vector<Eigen::MatrixXd>& workspace) {
  if (K > static_cast<int>(allowed.size())) {
    throw std::invalid_argument("plan: " + std::to_string(K) + " poses asked for, " + std::to_string(allowed.size()) +
                                " candidates meet the constraints");
  }
  const int p = static_cast<int>(model.prior.rows());
  const Eigen::MatrixXd W = criterion == "I" ? MeanGram(workspace, p) : Eigen::MatrixXd();
  Eigen::MatrixXd C = model.prior.inverse();
  std::vector<char> taken(model.rows.size(), 0);
  std::vector<int> chosen;
  for (int k = 0; k < K; ++k) {
    double best = -std::numeric_limits<double>::infinity();
    int best_index = -1;
    for (int i : allowed) {
      if (taken[i]) continue;
      const Eigen::MatrixXd G = model.rows[i] * C;
      const double gain = Gain(criterion, G, model.rows[i], W);
      if (gain > best) best = gain, best_index = i;  // ties: the first candidate
    }
    const Eigen::MatrixXd& J = model.rows[best_index];
    const Eigen::MatrixXd G = J * C;
    const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(J.rows(), J.rows()) + G * J.transpose();
    C -= G.transpose() * S.llt().solve(G);
    C = 0.5 * (C + C.transpose());
    taken[best_index] = 1;
    chosen.push_back(best_index);
  }
  return chosen;
}

DesignScores ScoreDesign(const InformationModel& model, const std::vector<int>& chosen,
                         const std::vector<Eigen::MatrixXd>& workspace) {
  Eigen::MatrixXd M = model.prior;
  for (int i : chosen) M.noalias() += model.rows[i].transpose() * model.rows[i];
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  const Eigen::MatrixXd C = llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
  DesignScores s;
  s.log_det = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  s.trace_c = C.trace();
  s.trace_wc = (MeanGram(workspace, static_cast<int>(M.rows())) * C).trace();
  return s;
}

}  // namespace kincal
