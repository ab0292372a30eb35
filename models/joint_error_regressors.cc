// The regressors of models/joint_errors.h and their analytic derivatives.
//
// Gravity terms move with the frames. A joint or a parameter changes the frames beyond it by one rigid
// twist (v, w) in the measurement frame, read off the Jacobians with the measurement-frame origin as
// reference point: a point p moves by v + w x p, a direction e by w x e. Joint m (0-based) moves frames
// m+1.. (its op sits in link m+1); a parameter of row r moves frames r..; tool parameters move no link
// frame. Base parameters turn every frame and the gravity direction alike, and the regressors, being
// triple products, are invariant under that: their derivative is zero.
#include <cmath>
#include <stdexcept>

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
      case T::kHarmonic:
        for (int h : term.orders) {
          const double s = std::sin(h * qbar[i]), c = std::cos(h * qbar[i]);
          phi[k] = s;
          phi[k + 1] = c;
          if (d.d_qbar) {
            (*d.d_qbar)(k, i) = h * c;
            (*d.d_qbar)(k + 1, i) = -h * s;
          }
          k += 2;
        }
        break;
      case T::kBacklash:
        if (qbar_previous) {
          const double dq = qbar[i] - (*qbar_previous)[i];
          phi[k] = (dq > 0) - (dq < 0);
        }
        ++k;
        break;
      case T::kApproach: {
        const Eigen::VectorXd* v = context.velocity_limits;
        if (!v || v->size() != n) throw std::invalid_argument("approach terms need velocity_limits, one per joint");
        if (qbar_previous) {
          const Eigen::VectorXd dq = qbar - *qbar_previous;
          // The move's duration: the slowest joint's |dq_j| / v_j.
          int slowest = 0;
          double duration = 0.0;
          for (int j = 0; j < n; ++j) {
            const double t = std::abs(dq[j]) / (*v)[j];
            if (t > duration) duration = t, slowest = j;
          }
          if (duration > 0.0) {
            phi[k] = dq[i] / duration;
            if (d.d_qbar || d.d_previous) {
              Eigen::VectorXd grad = Eigen::VectorXd::Zero(n);
              grad[i] += 1.0 / duration;
              grad[slowest] -= dq[i] / (duration * duration) * (dq[slowest] > 0 ? 1.0 : -1.0) / (*v)[slowest];
              if (d.d_qbar) d.d_qbar->row(k) = grad.transpose();
              if (d.d_previous) d.d_previous->row(k) = -grad.transpose();
            }
          }
        }
        ++k;
        break;
      }
    }
  }
  return phi;
}

}  // namespace kincal
