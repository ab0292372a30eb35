#include "doctor/cheap_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "estimators/error_model/base_registration.h"
#include "framework/math.h"
#include "robot/joint_readings.h"
#include "robot/prediction.h"

namespace kincal::doctor {
namespace {

// What the fit holds fixed per row: the actual joint angles from the file's readings, the session, the
// marker's index.
struct Rows {
  std::vector<Eigen::VectorXd> q;
  std::vector<int> session, marker;  // indices into the parameter blocks
  std::vector<int> session_ids;
  std::vector<std::string> marker_ids;
};

Rows PrepareRows(const Robot& robot, const Dataset& data) {
  Rows rows;
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::map<int, int> sessions;
  std::map<std::string, int> markers;
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    rows.q.push_back(ActualJointAngles(robot, robot, data, i, previous));
    if (!sessions.count(m.session)) {
      sessions[m.session] = static_cast<int>(rows.session_ids.size());
      rows.session_ids.push_back(m.session);
    }
    if (!markers.count(m.marker)) {
      markers[m.marker] = static_cast<int>(rows.marker_ids.size());
      rows.marker_ids.push_back(m.marker);
    }
    rows.session.push_back(sessions[m.session]);
    rows.marker.push_back(markers[m.marker]);
  }
  return rows;
}

// The fit's parameters as plain values (frames as corrections of the session's base).
struct State {
  std::vector<Eigen::Isometry3d> frames;
  std::vector<Eigen::Vector3d> markers;
  Eigen::VectorXd offsets;
};

Eigen::Vector3d Predict(const Robot& robot, const Rows& rows, const State& s, size_t i, const Dataset& data) {
  const Eigen::Isometry3d T = PredictToolPose(robot, rows.q[i] + s.offsets, data.rows[i].session);
  return s.frames[rows.session[i]] * (T * s.markers[rows.marker[i]]);
}

// Each session's frame registered in closed form on the points the file's geometry predicts.
void RegisterFrames(const Robot& robot, const Rows& rows, const Dataset& data, State* s) {
  std::vector<PointRegistration> reg(rows.session_ids.size());
  std::vector<Eigen::Vector3d> sum_a(reg.size(), Eigen::Vector3d::Zero()), sum_b = sum_a;
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Eigen::Vector3d a = PredictToolPose(robot, rows.q[i], data.rows[i].session) * s->markers[rows.marker[i]];
    reg[rows.session[i]].Add(a, data.rows[i].p);
    sum_a[rows.session[i]] += a;
    sum_b[rows.session[i]] += data.rows[i].p;
  }
  for (size_t k = 0; k < reg.size(); ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (!reg[k].Solve(&T) && reg[k].count() > 0) T.translation() = (sum_b[k] - sum_a[k]) / reg[k].count();
    s->frames[k] = T;
  }
}

double HuberCost(const std::vector<double>& r, double c) {
  double sum = 0.0;
  for (double x : r) sum += x <= c ? 0.5 * x * x : c * (x - 0.5 * c);
  return sum;
}

std::vector<double> Norms(const Robot& robot, const Rows& rows, const State& s, const Dataset& data) {
  std::vector<double> out(data.rows.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = (Predict(robot, rows, s, i, data) - data.rows[i].p).norm();
  return out;
}

// One Levenberg-Marquardt step on the Huber cost with threshold c; false when no damping makes it better.
bool Step(const Robot& robot, const Rows& rows, const Dataset& data, const CheapFitOptions& options, double c,
          double prior_weight, double* damping, State* s) {
  const int n = static_cast<int>(s->offsets.size());
  const int nf = 6 * static_cast<int>(s->frames.size());
  const int nm = options.free_markers ? 3 * static_cast<int>(s->markers.size()) : 0;
  const int np = nf + nm + n;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(np, np);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(np);
  const double h = 1e-6;
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const int session = data.rows[i].session;
    const Eigen::Isometry3d& C = s->frames[rows.session[i]];
    const Eigen::Vector3d& m = s->markers[rows.marker[i]];
    const Eigen::Isometry3d T = PredictToolPose(robot, rows.q[i] + s->offsets, session);
    const Eigen::Vector3d y = C * (T * m);
    const Eigen::Vector3d r = y - data.rows[i].p;
    const double norm = r.norm();
    const double w = norm <= c ? 1.0 : c / norm;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3, np);
    const int f = 6 * rows.session[i];
    J.block<3, 3>(0, f) = -Skew(y);
    J.block<3, 3>(0, f + 3) = Eigen::Matrix3d::Identity();
    if (options.free_markers) J.block<3, 3>(0, nf + 3 * rows.marker[i]) = C.linear() * T.linear();
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd q = rows.q[i] + s->offsets;
      q[j] += h;
      J.col(nf + nm + j) = C.linear() * ((PredictToolPose(robot, q, session) * m - T * m) / h);
    }
    H.noalias() += w * J.transpose() * J;
    g.noalias() += w * J.transpose() * r;
  }
  for (int j = 0; j < n; ++j) {
    H(nf + nm + j, nf + nm + j) += prior_weight;
    g[nf + nm + j] += prior_weight * s->offsets[j];
  }
  const auto cost = [&](const State& t) {
    return HuberCost(Norms(robot, rows, t, data), c) + 0.5 * prior_weight * t.offsets.squaredNorm();
  };
  const double before = cost(*s);
  for (int attempt = 0; attempt < 6; ++attempt) {
    Eigen::MatrixXd A = H;
    A.diagonal() += *damping * H.diagonal() + Eigen::VectorXd::Constant(np, 1e-12 * (1.0 + H.diagonal().maxCoeff()));
    const Eigen::VectorXd dx = -A.ldlt().solve(g);
    if (!dx.allFinite()) return false;
    State t = *s;
    for (size_t k = 0; k < t.frames.size(); ++k) {
      Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
      D.linear() = RotationExp(dx.segment<3>(6 * k));
      D.translation() = dx.segment<3>(6 * k + 3);
      t.frames[k] = D * t.frames[k];
    }
    if (options.free_markers) {
      for (size_t k = 0; k < t.markers.size(); ++k) t.markers[k] += dx.segment<3>(nf + 3 * k);
    }
    // Bounded: a zero a quarter turn off is a finding of its own (doctor.h), not a correction to absorb.
    t.offsets = (t.offsets + dx.tail(n)).cwiseMax(-options.max_offset).cwiseMin(options.max_offset);
    if (cost(t) < before) {
      *s = t;
      *damping = std::max(1e-9, *damping / 10.0);
      return true;
    }
    *damping *= 10.0;
  }
  return false;
}

}  // namespace

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double TrimmedRms(const std::vector<Eigen::Vector3d>& residuals, double trim) {
  std::vector<double> sq;
  for (const auto& r : residuals) sq.push_back(r.squaredNorm());
  if (sq.empty()) return 0.0;
  std::sort(sq.begin(), sq.end());
  const size_t keep = std::max<size_t>(1, static_cast<size_t>(std::ceil(trim * static_cast<double>(sq.size()))));
  double sum = 0.0;
  for (size_t i = 0; i < keep; ++i) sum += sq[i];
  const double out = std::sqrt(sum / static_cast<double>(keep));
  return std::isfinite(out) ? out : std::numeric_limits<double>::infinity();
}

CheapFit FitCheap(const Robot& robot, const Dataset& data, const CheapFitOptions& options) {
  const Rows rows = PrepareRows(robot, data);
  State s;
  s.frames.resize(rows.session_ids.size(), Eigen::Isometry3d::Identity());
  for (const auto& id : rows.marker_ids) s.markers.push_back(robot.MarkerPosition(id));
  s.offsets = Eigen::VectorXd::Zero(robot.dof());
  RegisterFrames(robot, rows, data, &s);
  const double prior_weight = static_cast<double>(data.rows.size()) * 1e-6 /
                              (options.offset_prior_sd * options.offset_prior_sd);
  double damping = 1e-3;
  for (int it = 0; it < options.iterations; ++it) {
    const double c = std::max(1e-6, 2.0 * Median(Norms(robot, rows, s, data)));
    if (!Step(robot, rows, data, options, c, prior_weight, &damping, &s)) break;
  }
  CheapFit fit;
  for (size_t k = 0; k < s.frames.size(); ++k) fit.frames[rows.session_ids[k]] = s.frames[k];
  for (size_t k = 0; k < s.markers.size(); ++k) fit.markers[rows.marker_ids[k]] = s.markers[k];
  fit.offsets = s.offsets;
  fit.residuals = Residuals(robot, data, fit);
  fit.score = TrimmedRms(fit.residuals, options.trim);
  fit.rms = TrimmedRms(fit.residuals, 1.0);
  return fit;
}

std::vector<Eigen::Vector3d> Residuals(const Robot& robot, const Dataset& data, const CheapFit& fit) {
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::vector<Eigen::Vector3d> out(data.rows.size());
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    const auto frame = fit.frames.find(m.session);
    const auto marker = fit.markers.find(m.marker);
    const Eigen::Isometry3d C = frame != fit.frames.end() ? frame->second : Eigen::Isometry3d::Identity();
    const Eigen::Vector3d p = marker != fit.markers.end() ? marker->second : robot.MarkerPosition(m.marker);
    const Eigen::VectorXd q = ActualJointAngles(robot, robot, data, i, previous) + fit.offsets;
    out[i] = C * (PredictToolPose(robot, q, m.session) * p) - m.p;
  }
  return out;
}

}  // namespace kincal::doctor
