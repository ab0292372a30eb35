// ErrorModelProblem's pose predictor (error_model_problem.h): the workspace set to x, the row's actual
// joint angles, its predicted pose and the pose Jacobian by the chain rule; EvaluateRow hands them to the
// row's factor (factor.h).
#include <stdexcept>
#include <string>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/pose_jacobians.h"
#include "framework/math.h"
#include "robot/joint_readings.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;

}  // namespace

JointErrorContext ErrorModelProblem::ContextOf(const Workspace& ws) const {
  JointErrorContext c = JointErrorContextOf(start_);
  c.model = ws.model.get();
  return c;
}

std::unique_ptr<ErrorModelProblem::Workspace> ErrorModelProblem::NewWorkspace() const {
  auto ws = std::make_unique<Workspace>();
  ws->model = start_.model().Clone();
  ws->joint_errors = start_.joint_errors;
  ws->active_joint_errors = active_joint_errors_;
  if (joint_errors_active_) ws->regressors = PreparedRegressors(active_joint_errors_, *ws->model);
  return ws;
}

void ErrorModelProblem::UpdateWorkspace(const Eigen::VectorXd& x, Workspace* ws) const {
  if (x.size() != num_parameters()) {
    throw std::invalid_argument("error model: x has " + std::to_string(x.size()) + " entries, expected " +
                                std::to_string(num_parameters()));
  }
  if (ws->valid && ws->x.size() == x.size() && ws->x == x) return;
  ws->x = x;
  Eigen::VectorXd values = start_.model().Parameters();
  for (size_t j = 0; j < model_column_.size(); ++j) {
    if (model_column_[j] >= 0) values[j] = x[model_column_[j]];
  }
  ws->model->SetParameters(values);
  const int n = start_.dof();
  ws->scale.setOnes(n);
  for (int i = 0; i < n; ++i) {
    if (ratio_column_[i] >= 0) ws->scale[i] = x[ratio_column_[i]];
  }
  if (!start_.joint_errors.empty()) {
    Eigen::VectorXd c = start_.joint_errors.Coefficients();
    for (size_t k = 0; k < joint_error_column_.size(); ++k) {
      if (joint_error_column_[k] >= 0) c[static_cast<Eigen::Index>(k)] = x[joint_error_column_[k]];
    }
    ws->joint_errors.SetCoefficients(c);
    Eigen::VectorXd active(static_cast<Eigen::Index>(active_coefficient_.size()));
    for (size_t a = 0; a < active_coefficient_.size(); ++a)
      active[static_cast<Eigen::Index>(a)] = c[active_coefficient_[a]];
    if (ws->active_joint_errors.num_coefficients() != active.size()) ws->active_joint_errors = active_joint_errors_;
    ws->active_joint_errors.SetCoefficients(active);
  }
  ws->markers.resize(marker_ids_.size());
  for (size_t k = 0; k < marker_ids_.size(); ++k) {
    ws->markers[k] = start_.MarkerPosition(marker_ids_[k]);
    for (int a = 0; a < 3; ++a) {
      if (marker_column_[k][a] >= 0) ws->markers[k][a] = x[marker_column_[k][a]];
    }
  }
  const Eigen::Isometry3d base0_inverse = ws->model->base().inverse();
  ws->session_pose.resize(session_ids_.size());
  ws->session_base.resize(session_ids_.size());
  ws->session_from_base0.resize(session_ids_.size());
  for (size_t k = 0; k < session_ids_.size(); ++k) {
    Vector6d pose = XyzRpyFromPose(start_.SessionBase(session_ids_[k]));
    for (int a = 0; a < 6; ++a) {
      if (session_column_[k][a] >= 0) pose[a] = x[session_column_[k][a]];
    }
    ws->session_pose[k] = pose;
    ws->session_base[k] = PoseFromXyzRpy(pose.head<3>(), pose.tail<3>());
    ws->session_from_base0[k] = ws->session_base[k] * base0_inverse;
  }
  ws->fixtures.resize(fixture_slots_.size());
  for (size_t k = 0; k < fixture_slots_.size(); ++k) {
    ws->fixtures[k] = fixture_slots_[k].start;
    for (int a = 0; a < 3; ++a) {
      if (fixture_column_[k][a] >= 0) ws->fixtures[k].x[a] = x[fixture_column_[k][a]];
    }
  }
  ws->valid = true;
}

// What RowJacobian needs of the row's pose, from EvaluateRow.
struct ErrorModelProblem::RowPose {
  int marker = -1, session = -1;
  bool has_previous = false;
  Eigen::Vector3d point, p;  // the marker in the tool frame; its predicted position (measurement frame)
  Eigen::Isometry3d T_meas_tool;
};

bool ErrorModelProblem::RowJointAngles(int row, bool jacobian, Workspace* ws) const {
  const int n = start_.dof();
  const Eigen::Map<const Eigen::VectorXd> q_ref(&rows_->q_ref[static_cast<size_t>(row) * n], n);
  ws->qbar = q_ref.cwiseQuotient(ws->scale);
  // Joint errors (models/joint_errors.h eq. 1) with the previous pose's drive angles.
  const bool has_previous = !rows_->has_previous.empty() && rows_->has_previous[row];
  if (!joint_errors_active_) {
    ws->q = ws->qbar;
    return has_previous;
  }
  JointErrorMap& map = ws->joint_error_map;
  if (has_previous) {
    ws->qbar_previous =
        Eigen::Map<const Eigen::VectorXd>(&rows_->q_prev_ref[static_cast<size_t>(row) * n], n).cwiseQuotient(ws->scale);
  }
  const JointErrorMap::Want want{jacobian && ratio_block_ >= 0, jacobian && ratio_block_ >= 0 && has_previous,
                                 jacobian && geometry_block_ >= 0 && gravity_terms_};
  ws->regressors.EvaluateMap(ws->active_joint_errors, ContextOf(*ws), ws->qbar,
                             has_previous ? &ws->qbar_previous : nullptr, want, &ws->regressor_row, &map);
  ws->q = map.q;
  return has_previous;
}

void ErrorModelProblem::PredictRowPose(int row, const Eigen::VectorXd& x, Workspace* ws, PredictedPose* predicted,
                                       Matrix6Xd* jacobian) const {
  UpdateWorkspace(x, ws);
  RowPose pose;
  pose.has_previous = RowJointAngles(row, jacobian != nullptr, ws);
  pose.marker = rows_->marker[row];
  pose.point = pose.marker >= 0 ? ws->markers[pose.marker] : Eigen::Vector3d::Zero();
  Matrix6Xd& Jm = ws->J_model;

  Eigen::Isometry3d& T_meas_tool = pose.T_meas_tool;
  if (jacobian) {
    T_meas_tool = ws->model->ParameterJacobian(ws->q, pose.point, &Jm);
  } else {
    T_meas_tool = ws->model->ForwardKinematics(ws->q);
  }
  pose.session = rows_->session[row];
  if (pose.session >= 0) {
    // T_meas(k)_tool = B_k B_0^-1 T_meas(0)_tool: derivatives rotate with it, the model base drops out.
    const Eigen::Isometry3d& M = ws->session_from_base0[pose.session];
    T_meas_tool = M * T_meas_tool;
    if (jacobian) {
      Jm.topRows<3>() = M.linear() * Jm.topRows<3>();
      Jm.bottomRows<3>() = M.linear() * Jm.bottomRows<3>();
    }
  }
  pose.p = T_meas_tool * pose.point;
  predicted->p = pose.p;
  predicted->R = T_meas_tool.linear();
  if (jacobian) RowJacobian(pose, ws, jacobian);
}

int ErrorModelProblem::EvaluateRow(int row, const Eigen::VectorXd& x, Workspace* ws, Vector6d* residual,
                                   Matrix6Xd* jacobian) const {
  PredictedPose pose;
  PredictRowPose(row, x, ws, &pose, jacobian);
  const int fixture = rows_->fixture[row];
  const FixtureValue* value = fixture >= 0 ? &ws->fixtures[fixture] : nullptr;
  const int k = rows_->factor[row]->Evaluate(data_->rows[row], factor_context(), pose, value, residual, jacobian,
                                             fixture >= 0 && jacobian ? &ws->J_fixture : nullptr);
  // The rows past k are zero, so that callers may read all six (fixed sizes for a point's 3: the common
  // case runs per row, where a dynamic row count costs a loop per column).
  if (k == 3) {
    residual->tail<3>().setZero();
    if (jacobian && jacobian->cols() > 0) jacobian->bottomRows<3>().setZero();
  } else if (k < 6) {
    residual->tail(6 - k).setZero();
    if (jacobian && jacobian->cols() > 0) jacobian->bottomRows(6 - k).setZero();
  }
  if (jacobian && fixture >= 0) {
    for (int a = 0; a < 3; ++a) {
      const int c = fixture_column_[fixture][a];
      if (c >= 0) jacobian->col(c).head(k) = ws->J_fixture.col(a).head(k);
    }
  }
  return k;
}

void ErrorModelProblem::RowJacobian(const RowPose& pose, Workspace* ws, Matrix6Xd* jacobian) const {
  const int n = start_.dof();
  const int session = pose.session, marker = pose.marker;
  const JointErrorMap& map = ws->joint_error_map;
  const Matrix6Xd& Jm = ws->J_model;
  Matrix6Xd& J = *jacobian;
  J.setZero(6, num_parameters());
  // The joint columns at the actual angles (measurement frame of the row's session), for the chain rule
  // through ratios and joint errors: the model's own columns where a joint adds to a parameter.
  Matrix6Xd& Jq = ws->J_joints;
  bool all_joint_parameters = true;
  for (int i = 0; i < n; ++i) all_joint_parameters = all_joint_parameters && joint_parameter_[i] >= 0;
  if (joint_errors_active_ || ratio_block_ >= 0) {
    if (all_joint_parameters) {
      Jq.resize(6, n);
      for (int i = 0; i < n; ++i) Jq.col(i) = Jm.col(joint_parameter_[i]);
    } else {
      Jq = ws->model->JointJacobian(ws->q, pose.point);
      if (session >= 0) {
        const Eigen::Matrix3d& R = ws->session_from_base0[session].linear();
        Jq.topRows<3>() = R * Jq.topRows<3>();
        Jq.bottomRows<3>() = R * Jq.bottomRows<3>();
      }
    }
  }
  const bool gravity_geometry = joint_errors_active_ && gravity_terms_ && geometry_block_ >= 0;
  for (size_t j = 0; j < model_column_.size(); ++j) {
    const int c = model_column_[j];
    if (c < 0) continue;
    if (session >= 0 && free_[c].group == Group::kBase) continue;
    J.col(c) = Jm.col(j);
    if (gravity_geometry && free_[c].group != Group::kBase)
      J.col(c) += Jq * map.dq_dparameters.col(static_cast<Eigen::Index>(j));
  }
  for (int i = 0; i < n; ++i) {
    const int c = ratio_column_[i];
    if (c < 0) continue;
    if (!joint_errors_active_) {
      // q_i = q_ref,i / s_i: dq_i/ds_i = -q_i / s_i.
      J.col(c) = Jq.col(i) * (-ws->q[i] / ws->scale[i]);
      continue;
    }
    // qbar_i = q_ref,i / s_i (and the previous pose's likewise), then q = qbar + dq(qbar, qbar_previous).
    Eigen::VectorXd dq_ds = map.dq_dqbar.col(i) * (-ws->qbar[i] / ws->scale[i]);
    if (pose.has_previous) dq_ds += map.dq_dprevious.col(i) * (-ws->qbar_previous[i] / ws->scale[i]);
    J.col(c) = Jq * dq_ds;
  }
  if (joint_errors_active_) {
    // Free coefficients belong to active terms: map.phi holds the active ones' regressors.
    for (size_t a = 0; a < active_coefficient_.size(); ++a) {
      const int k = active_coefficient_[a];
      const int c = joint_error_column_[k];
      if (c >= 0) J.col(c) = Jq.col(coefficient_joints_[k]) * map.phi[static_cast<Eigen::Index>(a)];
    }
  }
  if (marker >= 0) {
    for (int a = 0; a < 3; ++a) {
      const int c = marker_column_[marker][a];
      if (c >= 0) J.col(c).head<3>() = pose.T_meas_tool.linear().col(a);
    }
  }
  if (session >= 0) {
    const Vector6d& session_pose = ws->session_pose[session];
    const Matrix6d Jb = PoseParameterJacobian(session_pose.head<3>(), session_pose.tail<3>(), pose.p);
    for (int a = 0; a < 6; ++a) {
      const int c = session_column_[session][a];
      if (c >= 0) J.col(c) = Jb.col(a);
    }
  }
}

}  // namespace kincal
