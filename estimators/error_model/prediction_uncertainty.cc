#include "estimators/error_model/prediction_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "estimators/error_model/covariance.h"
#include "framework/median.h"

namespace kincal {
namespace {

// Per row of `problem` at x: sqrt(trace(J_S C J_S^T)) over the columns `columns` (problem column ->
// covariance index, -1 when absent), J the predicted marker position's Jacobian (the pose predictor's),
// so that every kind of row gets the sd of its predicted point.
std::vector<double> RowSd(const ErrorModelProblem& problem, const Eigen::VectorXd& x, const Eigen::MatrixXd& C,
                          const std::vector<int>& columns, int rows) {
  std::vector<int> used, index;
  for (size_t j = 0; j < columns.size(); ++j) {
    if (columns[j] >= 0) used.push_back(static_cast<int>(j)), index.push_back(columns[j]);
  }
  const int q = static_cast<int>(used.size());
  Eigen::MatrixXd Cs(q, q);
  for (int a = 0; a < q; ++a)
    for (int b = 0; b < q; ++b) Cs(a, b) = C(index[a], index[b]);
  auto ws = problem.NewWorkspace();
  PredictedPose pose;
  Matrix6Xd J;
  Eigen::MatrixXd Js(3, q);
  std::vector<double> out(rows);
  for (int i = 0; i < rows; ++i) {
    problem.PredictRowPose(i, x, ws.get(), &pose, &J);
    // A row the model cannot evaluate (non-finite values) leaves J without its columns.
    if (J.cols() != static_cast<Eigen::Index>(columns.size()) || !J.allFinite()) {
      out[i] = NAN;
      continue;
    }
    for (int a = 0; a < q; ++a) Js.col(a) = J.col(used[a]).head<3>();
    const double variance = (Js * Cs * Js.transpose()).trace();
    out[i] = variance > 0.0 ? std::sqrt(variance) : (variance == 0.0 ? 0.0 : NAN);
  }
  return out;
}

}  // namespace

nlohmann::json PredictionCovariance::ToJson() const {
  nlohmann::json j;
  j["names"] = names;
  j["unit"] = "SI (m, rad, ratio scale, joint error coefficients' SI units)";
  j["sigma_m"] = sigma;
  j["median_train_sd_m"] = median_train_sd;
  j["support_factor"] = kSupportFactor;
  j["inadequacy_m"] = inadequacy;
  if (!inadequacy_beyond.empty()) j["inadequacy_beyond_m"] = inadequacy_beyond;
  j["inadequacy_source"] = inadequacy_source;
  if (joint_min.size() > 0) {
    j["joint_min"] = std::vector<double>(joint_min.data(), joint_min.data() + joint_min.size());
    j["joint_max"] = std::vector<double>(joint_max.data(), joint_max.data() + joint_max.size());
    j["joint_margin"] = kJointMargin;
  }
  nlohmann::json m = nlohmann::json::array();
  for (Eigen::Index a = 0; a < matrix.rows(); ++a) {
    std::vector<double> row(matrix.cols());
    for (Eigen::Index b = 0; b < matrix.cols(); ++b) row[b] = matrix(a, b);
    m.push_back(row);
  }
  j["matrix"] = m;
  return j;
}

PredictionCovariance PredictionCovariance::FromJson(const nlohmann::json& j) {
  PredictionCovariance c;
  try {
    c.names = j.at("names").get<std::vector<std::string>>();
    c.sigma = j.at("sigma_m").is_number() ? j.at("sigma_m").get<double>() : NAN;
    c.median_train_sd = j.at("median_train_sd_m").is_number() ? j.at("median_train_sd_m").get<double>() : NAN;
    if (j.contains("inadequacy_m")) {
      c.inadequacy = j.at("inadequacy_m").get<double>();
      if (!(c.inadequacy >= 0.0) || !std::isfinite(c.inadequacy))
        throw std::invalid_argument("inadequacy_m must be finite and >= 0");
      c.inadequacy_source = j.value("inadequacy_source", std::string("cross-validation"));
    }
    if (j.contains("inadequacy_beyond_m")) {
      c.inadequacy_beyond = j.at("inadequacy_beyond_m").get<std::vector<double>>();
      for (double t : c.inadequacy_beyond)
        if (!(t >= 0.0) || !std::isfinite(t)) throw std::invalid_argument("inadequacy_beyond_m must be finite and >= 0");
    }
    if (j.contains("joint_min") || j.contains("joint_max")) {
      const auto lo = j.at("joint_min").get<std::vector<double>>(), hi = j.at("joint_max").get<std::vector<double>>();
      if (lo.size() != hi.size()) throw std::invalid_argument("joint_min and joint_max differ in length");
      c.joint_min = Eigen::Map<const Eigen::VectorXd>(lo.data(), static_cast<Eigen::Index>(lo.size()));
      c.joint_max = Eigen::Map<const Eigen::VectorXd>(hi.data(), static_cast<Eigen::Index>(hi.size()));
    }
    const auto& m = j.at("matrix");
    const size_t p = c.names.size();
    if (m.size() != p) throw std::invalid_argument("the covariance matrix does not match its names");
    c.matrix.resize(p, p);
    for (size_t a = 0; a < p; ++a) {
      if (m[a].size() != p) throw std::invalid_argument("the covariance matrix does not match its names");
      for (size_t b = 0; b < p; ++b) c.matrix(a, b) = m[a][b].is_number() ? m[a][b].get<double>() : NAN;
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("prediction_covariance: ") + e.what());
  }
  return c;
}

PredictionCovariance ComputePredictionCovariance(const PreparedErrorModel& prep, const Eigen::VectorXd& x,
                                                 const RowWeighting& weighting) {
  const ErrorModelProblem& problem = *prep.problem;
  const int p = problem.num_parameters();
  const NormalEquations ne = NormalEquationsAt(prep, x, weighting);
  PredictionCovariance c;
  c.names = problem.ParameterNames();
  if (p == 0) return c;  // every parameter held: nothing to propagate
  c.sigma = ne.num_residuals > p ? std::sqrt(ne.irls_squares / (ne.num_residuals - p)) : NAN;
  if (!std::isfinite(c.sigma)) {
    c.matrix = Eigen::MatrixXd::Constant(p, p, NAN);
    return c;
  }
  c.matrix = c.sigma * c.sigma * ScaledPseudoInverse(ne.JtJ);
  if (!c.matrix.allFinite()) return c;
  std::vector<int> columns(c.names.size());
  for (size_t j = 0; j < columns.size(); ++j) columns[j] = static_cast<int>(j);
  c.median_train_sd = Median(RowSd(problem, x, c.matrix, columns, problem.num_rows()));
  for (const Measurement& m : problem.data().rows) {
    if (c.joint_min.size() == 0) {
      c.joint_min = c.joint_max = m.q;
    } else if (m.q.size() == c.joint_min.size()) {
      c.joint_min = c.joint_min.cwiseMin(m.q);
      c.joint_max = c.joint_max.cwiseMax(m.q);
    }
  }
  return c;
}

bool PredictionCovariance::BeyondJointRange(const Eigen::VectorXd& q) const {
  if (joint_min.size() == 0 || q.size() != joint_min.size()) return false;
  return ((q - joint_max).array() > kJointMargin).any() || ((joint_min - q).array() > kJointMargin).any();
}

bool PredictionCovariance::OutsideSupport(double sd, const Eigen::VectorXd& q) const {
  return sd > SupportThreshold() || BeyondJointRange(q);
}

double PredictionCovariance::Inadequacy(const Eigen::VectorXd& q) const {
  double tau = inadequacy;
  if (joint_min.size() == 0 || q.size() != joint_min.size()) return tau;
  for (Eigen::Index j = 0; j < q.size() && j < static_cast<Eigen::Index>(inadequacy_beyond.size()); ++j) {
    if (q[j] - joint_max[j] > kJointMargin || joint_min[j] - q[j] > kJointMargin)
      tau = std::max(tau, inadequacy_beyond[j]);
  }
  return tau;
}

std::string InadequacySummary(const PredictionCovariance& c) {
  if (c.inadequacy_source == "none") {
    return "model inadequacy not measured (no select or cross_validate): sd_mm is the parameters' part only";
  }
  char line[120];
  std::snprintf(line, sizeof line, "model inadequacy tau (%s): %.4f mm within the training range",
                c.inadequacy_source.c_str(), c.inadequacy * 1e3);
  std::string out = line;
  if (!c.inadequacy_beyond.empty()) {
    out += "; beyond it, joint 1..n:";
    for (double t : c.inadequacy_beyond) {
      std::snprintf(line, sizeof line, " %.4f", t * 1e3);
      out += line;
    }
    out += " mm";
  }
  return out + " (sd_mm^2 = sd_param^2 + tau^2)";
}

double EstimateInadequacy(const InadequacySample& sample, int joint) {
  std::vector<size_t> rows;
  for (size_t i = 0; i < sample.squared_error.size(); ++i) {
    const auto& b = sample.beyond[i];
    const bool member = joint < 0 ? b.empty() : std::find(b.begin(), b.end(), joint) != b.end();
    if (member && std::isfinite(sample.expected[i]) && std::isfinite(sample.squared_error[i])) rows.push_back(i);
  }
  double tau2 = 0.0;
  for (int pass = 0; pass < 200; ++pass) {  // (3)'s fixed point: the weights depend on tau^2
    double sum_w = 0.0, sum_wx = 0.0;
    for (size_t i : rows) {
      const double v = sample.expected[i] + tau2;
      if (!(v > 0.0)) continue;
      sum_w += 1.0 / (v * v);
      sum_wx += (sample.squared_error[i] - sample.expected[i]) / (v * v);
    }
    if (!(sum_w > 0.0)) return 0.0;
    const double next = std::max(0.0, sum_wx / sum_w);
    const bool settled = std::abs(next - tau2) <= 1e-9 * next;
    tau2 = next;
    if (settled) break;
  }
  return std::sqrt(tau2);
}

std::vector<double> PredictionSd(const Robot& model, const Robot& controller, const Dataset& data,
                                 const PredictionCovariance& covariance) {
  if (data.rows.empty()) return {};
  // The problem needs more residuals than parameters: a short dataset is repeated (each row's Jacobian
  // depends only on the row and its previous pose, which the first copy keeps). The problem frees every
  // candidate the data can move, not only the covariance's: p bounds them all (geometry, joint-level
  // coefficients, ratios, markers, session bases), so that no count of the padded rows reaches the user.
  Dataset padded = data;
  const size_t p = static_cast<size_t>(model.model().num_parameters() + model.joint_errors.num_coefficients() +
                                       model.dof()) +
                   3 * model.markers.size() + 6 * model.session_bases.size() + covariance.names.size() + 64;
  while (padded.rows.size() * 3 <= p) padded.rows.insert(padded.rows.end(), data.rows.begin(), data.rows.end());
  ErrorModelOptions options;
  options.initialize_bases = false;
  const ErrorModelProblem problem(model, controller, padded, options);
  std::map<std::string, int> index;
  for (size_t j = 0; j < covariance.names.size(); ++j) index[covariance.names[j]] = static_cast<int>(j);
  std::vector<int> columns;
  for (const std::string& name : problem.ParameterNames()) {
    const auto it = index.find(name);
    columns.push_back(it == index.end() ? -1 : it->second);
  }
  return RowSd(problem, problem.InitialX(), covariance.matrix, columns, static_cast<int>(data.rows.size()));
}

nlohmann::json UncertaintyCheck::ToJson() const {
  return {{"rows", rows},
          {"outside_support", outside_support},
          {"coverage_3sigma", coverage},
          {"coverage_3sigma_1d", coverage_1d},
          {"coverage_3sigma_supported", coverage_supported}};
}

UncertaintyCheck CheckUncertainty(const std::vector<double>& errors, const std::vector<double>& sd,
                                  const PredictionCovariance& covariance, const Dataset& data) {
  UncertaintyCheck c;
  c.rows = static_cast<int>(std::min({errors.size(), sd.size(), data.rows.size()}));
  int inside = 0, inside_1d = 0, inside_supported = 0;
  const double s2 = covariance.sigma * covariance.sigma;
  for (int i = 0; i < c.rows; ++i) {
    const bool outside = covariance.OutsideSupport(sd[i], data.rows[i].q);  // on the parameters' part
    const double tau = covariance.Inadequacy(data.rows[i].q);
    const double pred2 = sd[i] * sd[i] + tau * tau;  // (2)
    const bool within = errors[i] <= 3.0 * std::sqrt(pred2 + 3.0 * s2);
    c.outside_support += outside;
    inside += within;
    inside_supported += within && !outside;
    if (errors[i] <= 3.0 * std::sqrt(pred2 + s2)) ++inside_1d;
  }
  if (c.rows > 0) c.coverage = static_cast<double>(inside) / c.rows;
  if (c.rows > 0) c.coverage_1d = static_cast<double>(inside_1d) / c.rows;
  if (c.rows > c.outside_support) {
    c.coverage_supported = static_cast<double>(inside_supported) / (c.rows - c.outside_support);
  }
  return c;
}

}  // namespace kincal
