// The regressors of models/joint_errors.h and their analytic derivatives.
//
// Gravity terms move with the frames. A joint or a parameter changes the frames beyond it by one rigid
// twist (v, w) in the measurement frame, read off the Jacobians with the measurement-frame origin as
// reference point: a point p moves by v + w x p, a direction e by w x e. Joint m (0-based) moves frames
// m+1.. (its op sits in link m+1); a parameter of row r moves frames r..; tool parameters move no link
// frame. Base parameters turn every frame and the gravity direction alike, and the regressors, being
// triple products, are invariant under that: their derivative is zero.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "models/joint_error_regressors.h"
#include "models/joint_errors.h"

namespace kincal {
namespace {

using T = JointErrorTerm::Type;

// The frames the gravity regressors use, and the twists that move them.
struct GravityFrames {
  std::vector<Eigen::Isometry3d> poses;  // T_meas_frame_j, j = 0..n, then the tool
  Eigen::Vector3d g;                     // gravity direction, measurement frame
  Matrix6Xd joint_twists;                // (v; w) per joint
  Matrix6Xd parameter_twists;            // (v; w) per model parameter
};

// One gravity regressor: link j's origin (component -1) or axis `component` against joint axis (w, a).
struct GravityRegressor {
  const GravityFrames* f;
  Eigen::Vector3d w, a;  // joint axis direction and a point on it
  int axis_frame, j, component;

  Eigen::Vector3d Arm() const {
    return component < 0 ? Eigen::Vector3d(f->poses[j].translation() - a)
                         : Eigen::Vector3d(f->poses[j].linear().col(component));
  }
  double Value() const { return w.dot(Arm().cross(f->g)); }
  // Derivative along a twist (v, om) that moves frames first.. .
  double Along(const Eigen::Vector3d& v, const Eigen::Vector3d& om, int first) const {
    const bool moves_axis = first <= axis_frame, moves_j = first <= j;
    const Eigen::Vector3d dw = moves_axis ? Eigen::Vector3d(om.cross(w)) : Eigen::Vector3d::Zero();
    Eigen::Vector3d d_arm = Eigen::Vector3d::Zero();
    if (component < 0) {
      if (moves_j) d_arm += v + om.cross(f->poses[j].translation());
      if (moves_axis) d_arm -= v + om.cross(a);
    } else if (moves_j) {
      d_arm = om.cross(f->poses[j].linear().col(component));
    }
    return dw.dot(Arm().cross(f->g)) + w.dot(d_arm.cross(f->g));
  }
};

int ComponentOf(const std::string& key) {
  const char last = key.back();
  if (key.size() >= 2 && key[key.size() - 2] == '_') return last - 'x';
  return -1;
}

int LinkOf(const std::string& key) {
  const size_t us = key.find('_');
  return std::stoi(key.substr(4, us == std::string::npos ? std::string::npos : us - 4));
}

// The regressors of a harmonic, backlash or approach term from coefficient k on, with their derivatives
// into the non-null matrices (rows k.. zero on entry).
void OtherTerm(const JointErrorTerm& term, int k, const JointErrorContext& context, const Eigen::VectorXd& qbar,
               const Eigen::VectorXd* qbar_previous, Eigen::VectorXd* phi_out, Eigen::MatrixXd* d_qbar,
               Eigen::MatrixXd* d_previous) {
  Eigen::VectorXd& phi = *phi_out;
  const int n = static_cast<int>(qbar.size());
  const int i = term.joint;
  switch (term.type) {
    case T::kGravity:
      break;
    case T::kHarmonic:
      for (int h : term.orders) {
        const double s = std::sin(h * qbar[i]), c = std::cos(h * qbar[i]);
        phi[k] = s;
        phi[k + 1] = c;
        if (d_qbar) {
          (*d_qbar)(k, i) = h * c;
          (*d_qbar)(k + 1, i) = -h * s;
        }
        k += 2;
      }
      break;
    case T::kBacklash:
      if (qbar_previous) {
        const double dq = qbar[i] - (*qbar_previous)[i];
        phi[k] = (dq > 0) - (dq < 0);
      }
      break;
    case T::kApproach: {
      const Eigen::VectorXd* v = context.velocity_limits;
      if (!v || v->size() != n) throw std::invalid_argument("approach terms need velocity_limits, one per joint");
      if (!qbar_previous) break;
      const Eigen::VectorXd dq = qbar - *qbar_previous;
      // The move's duration: the slowest joint's |dq_j| / v_j.
      int slowest = 0;
      double duration = 0.0;
      for (int j = 0; j < n; ++j) {
        const double t = std::abs(dq[j]) / (*v)[j];
        if (t > duration) duration = t, slowest = j;
      }
      if (!(duration > 0.0)) break;
      phi[k] = dq[i] / duration;
      if (d_qbar || d_previous) {
        Eigen::VectorXd grad = Eigen::VectorXd::Zero(n);
        grad[i] += 1.0 / duration;
        grad[slowest] -= dq[i] / (duration * duration) * (dq[slowest] > 0 ? 1.0 : -1.0) / (*v)[slowest];
        if (d_qbar) d_qbar->row(k) = grad.transpose();
        if (d_previous) d_previous->row(k) = -grad.transpose();
      }
      break;
    }
  }
}

}  // namespace

Eigen::VectorXd EvaluateRegressors(const JointErrors& errors, const JointErrorContext& context,
                                   const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous,
                                   const RegressorDerivatives& d) {
  const KinematicModel& model = *context.model;
  const int n = static_cast<int>(qbar.size());
  const int K = errors.num_coefficients();
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(K);
  if (d.d_qbar) d.d_qbar->setZero(K, n);
  if (d.d_previous) d.d_previous->setZero(K, n);
  if (d.d_parameters) d.d_parameters->setZero(K, model.num_parameters());

  bool gravity = false;
  for (const auto& t : errors.terms) gravity = gravity || t.type == T::kGravity;
  GravityFrames frames;
  if (gravity) {
    frames.poses = model.FramePoses(qbar);
    frames.g = frames.poses[0].linear() * context.gravity;
    const Eigen::Vector3d origin_in_tool = frames.poses.back().inverse().translation();
    if (d.d_qbar) frames.joint_twists = model.JointJacobian(qbar, origin_in_tool);
    if (d.d_parameters) model.ParameterJacobian(qbar, origin_in_tool, &frames.parameter_twists);
  }
  const auto& info = model.parameter_info();

  int k = 0;
  for (const auto& term : errors.terms) {
    const int i = term.joint;
    switch (term.type) {
      case T::kGravity: {
        const int fa = model.JointAxisFrame(i);
        for (const auto& key : term.keys) {
          const GravityRegressor r{
              &frames,         frames.poses[fa].linear().col(2), frames.poses[fa].translation(), fa, LinkOf(key),
              ComponentOf(key)};
          phi[k] = r.Value();
          if (d.d_qbar) {
            for (int m = 0; m < n; ++m) {
              (*d.d_qbar)(k, m) =
                  r.Along(frames.joint_twists.col(m).head<3>(), frames.joint_twists.col(m).tail<3>(), m + 1);
            }
          }
          if (d.d_parameters) {
            for (int p = 0; p < model.num_parameters(); ++p) {
              if (info[p].group == ParameterInfo::Group::kBase) continue;
              const int first = info[p].group == ParameterInfo::Group::kTool ? n + 1 : info[p].joint;
              (*d.d_parameters)(k, p) =
                  r.Along(frames.parameter_twists.col(p).head<3>(), frames.parameter_twists.col(p).tail<3>(), first);
            }
          }
          ++k;
        }
        break;
      }
      default:
        OtherTerm(term, k, context, qbar, qbar_previous, &phi, d.d_qbar, d.d_previous);
        k += static_cast<int>(term.keys.size());
        break;
    }
  }
  return phi;
}

PreparedRegressors::PreparedRegressors(const JointErrors& errors, const KinematicModel& model) {
  num_coefficients_ = errors.num_coefficients();
  terms_ = errors.terms;
  // The first frame each joint and parameter moves (n + 2 for base parameters: past every frame, as the
  // regressors do not change with the base).
  const int n = model.dof();
  for (int m = 0; m < n; ++m) joint_first_.push_back(m + 1);
  for (const ParameterInfo& info : model.parameter_info()) {
    parameter_first_.push_back(info.group == ParameterInfo::Group::kBase   ? n + 2
                               : info.group == ParameterInfo::Group::kTool ? n + 1
                                                                           : info.joint);
  }
  int k = 0;
  for (JointErrorTerm& term : terms_) {
    term.coefficients.resize(0);
    if (term.type == T::kGravity) {
      const int axis_frame = model.JointAxisFrame(term.joint);
      if (axis_frame < 0) throw std::invalid_argument("gravity terms need a model with joint axis frames");
      const int slot = static_cast<int>(gravity_joints_.size());
      gravity_joints_.push_back(term.joint);
      for (const auto& key : term.keys) {
        gravity_.push_back({k++, axis_frame, LinkOf(key), ComponentOf(key), slot});
        first_limit_ = std::max({first_limit_, axis_frame, gravity_.back().link});
      }
    } else {
      k += static_cast<int>(term.keys.size());
    }
  }
}

// Gravity rows: phi as GravityRegressor::Value, and where derivatives are wanted L_axis, L_link (the
// header) and the twists of the frames (reference point: the measurement frame's origin).
void PreparedRegressors::GravityRows(const JointErrorContext& context, const Eigen::VectorXd& qbar, Want want,
                                     Row* row) const {
  const KinematicModel& model = *context.model;
  const int G = static_cast<int>(gravity_.size());
  const std::vector<Eigen::Isometry3d> poses = model.FramePoses(qbar);
  const Eigen::Vector3d g = poses[0].linear() * context.gravity;  // measurement frame
  const bool derivatives = want.qbar || want.parameters;
  row->L_axis.resize(G, 6);
  row->L_link.resize(G, 6);
  for (int r = 0; r < G; ++r) {
    const Gravity& e = gravity_[r];
    const Eigen::Vector3d w = poses[e.axis_frame].linear().col(2), a = poses[e.axis_frame].translation();
    const Eigen::Vector3d arm = e.component < 0 ? Eigen::Vector3d(poses[e.link].translation() - a)
                                                : Eigen::Vector3d(poses[e.link].linear().col(e.component));
    row->phi[e.k] = w.dot(arm.cross(g));
    if (!derivatives) continue;
    const Eigen::Vector3d u = g.cross(w), turn = w.cross(arm.cross(g));
    if (e.component < 0) {
      row->L_axis.row(r) << (-u).transpose(), (turn - a.cross(u)).transpose();
      row->L_link.row(r) << u.transpose(), poses[e.link].translation().cross(u).transpose();
    } else {
      row->L_axis.row(r) << 0.0, 0.0, 0.0, turn.transpose();
      row->L_link.row(r) << 0.0, 0.0, 0.0, arm.cross(u).transpose();
    }
  }
  if (!derivatives) return;
  const Eigen::Vector3d origin_in_tool = poses.back().inverse().translation();
  if (want.qbar) row->joint_twists = model.JointJacobian(qbar, origin_in_tool);
  if (want.parameters) model.ParameterJacobian(qbar, origin_in_tool, &row->parameter_twists);
}

// Per gravity coefficient, its derivative along each twist: joint m moves frames m + 1.., a parameter of
// row r frames r.., a tool parameter none, a base parameter (first = n + 2) all, and the regressors are
// invariant under that: zero.
void PreparedRegressors::FillGravity(const Row& row, const Matrix6Xd& twists, const std::vector<int>& first,
                                     Eigen::MatrixXd* d) const {
  for (size_t r = 0; r < gravity_.size(); ++r) {
    const Gravity& e = gravity_[r];
    const Eigen::Matrix<double, 1, 6> L_axis = row.L_axis.row(r), L_link = row.L_link.row(r);
    for (int c = 0; c < twists.cols(); ++c) {
      const Vector6d t = twists.col(c);
      const double axis = first[c] <= e.axis_frame ? L_axis.dot(t) : 0.0;
      (*d)(e.k, c) = first[c] <= e.link ? axis + L_link.dot(t) : axis;
    }
  }
}

// The same summed into joint rows with the coefficients c (per gravity row): d q_i / d t = S_i(first) . t
// with S_i(f) = sum over joint i's gravity rows of c (L_axis [f <= axis frame] + L_link [f <= link]),
// suffix sums over f of the rows' terms placed at their frames.
void PreparedRegressors::ChainGravity(Row* row, const Matrix6Xd& twists, const std::vector<int>& first,
                                      Eigen::MatrixXd* dq) const {
  const int frames = first_limit_ + 1;
  row->sums.setZero(6, static_cast<Eigen::Index>(gravity_joints_.size()) * frames);
  for (size_t r = 0; r < gravity_.size(); ++r) {
    const Gravity& e = gravity_[r];
    const double c = row->c_gravity[static_cast<Eigen::Index>(r)];
    row->sums.col(e.slot * frames + e.axis_frame) += c * row->L_axis.row(r).transpose();
    row->sums.col(e.slot * frames + e.link) += c * row->L_link.row(r).transpose();
  }
  for (size_t slot = 0; slot < gravity_joints_.size(); ++slot) {
    for (int f = frames - 2; f >= 0; --f) row->sums.col(slot * frames + f) += row->sums.col(slot * frames + f + 1);
    for (int c = 0; c < twists.cols(); ++c) {
      if (first[c] >= frames) continue;
      (*dq)(gravity_joints_[slot], c) += row->sums.col(slot * frames + first[c]).dot(twists.col(c));
    }
  }
}

void PreparedRegressors::Evaluate(const JointErrorContext& context, const Eigen::VectorXd& qbar,
                                  const Eigen::VectorXd* qbar_previous, Want want, Row* row) const {
  const int n = static_cast<int>(qbar.size()), K = num_coefficients_;
  row->phi.setZero(K);
  if (want.qbar) row->d_qbar.setZero(K, n);
  if (want.previous) row->d_previous.setZero(K, n);
  if (want.parameters) row->d_parameters.setZero(K, context.model->num_parameters());
  if (!gravity_.empty()) {
    GravityRows(context, qbar, want, row);
    if (want.qbar) FillGravity(*row, row->joint_twists, joint_first_, &row->d_qbar);
    if (want.parameters) FillGravity(*row, row->parameter_twists, parameter_first_, &row->d_parameters);
  }
  OtherTerms(context, qbar, qbar_previous, want, row);
}

void PreparedRegressors::OtherTerms(const JointErrorContext& context, const Eigen::VectorXd& qbar,
                                    const Eigen::VectorXd* qbar_previous, Want want, Row* row) const {
  int k = 0;
  for (const JointErrorTerm& term : terms_) {
    if (term.type != T::kGravity) {
      OtherTerm(term, k, context, qbar, qbar_previous, &row->phi, want.qbar ? &row->d_qbar : nullptr,
                want.previous ? &row->d_previous : nullptr);
    }
    k += static_cast<int>(term.keys.size());
  }
}

void PreparedRegressors::EvaluateMap(const JointErrors& errors, const JointErrorContext& context,
                                     const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous,
                                     JointErrorMap::Want want, Row* row, JointErrorMap* out) const {
  if (errors.num_coefficients() != num_coefficients_ || errors.terms.size() != terms_.size()) {
    throw std::invalid_argument("PreparedRegressors: the joint errors are not the ones prepared for");
  }
  const int n = static_cast<int>(qbar.size()), K = num_coefficients_;
  // Regressors of every term; derivatives per coefficient only for the terms other than gravity (rows
  // of zeros for gravity), whose derivatives go into the joint rows directly.
  row->phi.setZero(K);
  if (want.qbar) row->d_qbar.setZero(K, n);
  if (want.previous) row->d_previous.setZero(K, n);
  const Want gravity_want{want.qbar, false, want.parameters};
  if (!gravity_.empty()) GravityRows(context, qbar, gravity_want, row);
  OtherTerms(context, qbar, qbar_previous, {want.qbar, want.previous, false}, row);
  ChainJointErrorMap(errors, qbar, row->phi, want.qbar ? &row->d_qbar : nullptr,
                     want.previous ? &row->d_previous : nullptr, nullptr, context.model->num_parameters(), out);
  if (want.parameters) out->dq_dparameters.setZero(n, context.model->num_parameters());
  if (gravity_.empty() || !(want.qbar || want.parameters)) return;
  row->c_gravity.resize(static_cast<Eigen::Index>(gravity_.size()));
  int k = 0;
  size_t r = 0;
  for (const JointErrorTerm& term : errors.terms) {
    for (Eigen::Index m = 0; m < term.coefficients.size(); ++m, ++k) {
      if (r < gravity_.size() && gravity_[r].k == k) row->c_gravity[static_cast<Eigen::Index>(r++)] = term.coefficients[m];
    }
  }
  if (want.qbar) ChainGravity(row, row->joint_twists, joint_first_, &out->dq_dqbar);
  if (want.parameters) ChainGravity(row, row->parameter_twists, parameter_first_, &out->dq_dparameters);
}

void ChainJointErrorMap(const JointErrors& errors, const Eigen::VectorXd& qbar, const Eigen::VectorXd& phi,
                        const Eigen::MatrixXd* d_qbar, const Eigen::MatrixXd* d_previous,
                        const Eigen::MatrixXd* d_parameters, int num_parameters, JointErrorMap* out) {
  const int n = static_cast<int>(qbar.size());
  out->phi = phi;
  out->q = qbar + JointOffsets(errors, phi, n);
  // Row joint(k) of each derivative gains c_k times row k of the regressors' derivative.
  const auto chain = [&](const Eigen::MatrixXd& d_phi, Eigen::MatrixXd* dq) {
    int k = 0;
    for (const auto& t : errors.terms) {
      for (Eigen::Index m = 0; m < t.coefficients.size(); ++m, ++k) dq->row(t.joint) += t.coefficients[m] * d_phi.row(k);
    }
  };
  if (d_qbar) {
    out->dq_dqbar.setIdentity(n, n);
    chain(*d_qbar, &out->dq_dqbar);
  }
  if (d_previous) {
    out->dq_dprevious.setZero(n, n);
    chain(*d_previous, &out->dq_dprevious);
  }
  if (d_parameters) {
    out->dq_dparameters.setZero(n, num_parameters);
    chain(*d_parameters, &out->dq_dparameters);
  }
}

}  // namespace kincal
