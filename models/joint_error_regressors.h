#pragma once
// The joint-level regressors of models/joint_errors.h for the many rows of one fit: the terms are laid out
// once (keys parsed, gravity terms indexed), then each row gets every coefficient's regressor and its
// derivatives in one pass, into storage kept between rows.
//
// The derivatives of the gravity regressors are the bulk of a fit's joint-level cost (EvaluateRegressors
// moves every regressor along every joint and parameter twist, one at a time). Here a gravity regressor
// phi = w . (arm x g) has, along a twist (v, om) that moves frames first.., the derivative
//     d phi = [first <= axis frame] L_axis . (v, om) + [first <= link frame] L_link . (v, om),
// linear in the twist, with u = g x w, c = arm x g:
//     origin terms (arm = o_j - a):   L_axis = (-u, w x c - a x u),   L_link = (u, o_j x u)
//     direction terms (arm = e):      L_axis = (0, w x c),            L_link = (0, e x u)
// (dw = om x w moves the axis, d arm the arm; triple products rearranged). So every derivative of a row
// comes from two K x 6 matrices and the 6 x (n + p) twists, masked by frame: a 6-term dot product per
// entry instead of a regressor moved along a twist. EvaluateMap goes further: equation (1) needs only
// sum_k c_k d phi_k per joint, so it sums c_k L over each joint's rows by frame first (suffix sums over
// the frames), and the cost of the gravity derivatives no longer grows with K. Regressors (phi) are
// computed as EvaluateRegressors computes them, to the bit; derivatives agree with it to rounding (the
// sums are associated differently).
//
// A fit calls, per workspace (the terms fixed, the coefficients and model parameters changing):
//     PreparedRegressors regressors(active_joint_errors, model);       // once
//     PreparedRegressors::Row row;                                     // kept in the workspace
//     regressors.EvaluateMap(active_joint_errors, context, qbar, previous_or_null, want, &row, &map);
// which fills the same JointErrorMap as EvaluateJointErrorMap (which stays, for one-off rows).
#include <vector>

#include <Eigen/Core>

#include "models/joint_errors.h"

namespace kincal {

class PreparedRegressors {
 public:
  PreparedRegressors() = default;
  // `errors` bound to `model` (JointErrors::Bind). Throws std::invalid_argument for a gravity term on a
  // model without joint axis frames.
  PreparedRegressors(const JointErrors& errors, const KinematicModel& model);

  int num_coefficients() const { return num_coefficients_; }

  struct Want {
    bool qbar = false, previous = false, parameters = false;
  };
  // One row's regressors and derivatives (those wanted; the others keep their size), and the scratch of
  // the pass. Reused between rows: no allocation once sized, beyond the model's frame poses.
  struct Row {
    Eigen::VectorXd phi;            // K
    Eigen::MatrixXd d_qbar;         // K x n
    Eigen::MatrixXd d_previous;     // K x n (zero without a previous pose)
    Eigen::MatrixXd d_parameters;   // K x model parameters (gravity rows only non-zero)
    // Scratch: gravity rows' L_axis and L_link (G x 6), the twists, and for EvaluateMap the rows'
    // coefficients and their sums per joint and frame.
    Eigen::Matrix<double, Eigen::Dynamic, 6> L_axis, L_link;
    Matrix6Xd joint_twists, parameter_twists;
    Eigen::VectorXd c_gravity;
    Eigen::Matrix<double, 6, Eigen::Dynamic> sums;
  };

  // phi(qbar, qbar_previous) and the wanted derivatives; context.model has the structure prepared for
  // (its parameter values may have changed since). qbar_previous null: no previous pose.
  void Evaluate(const JointErrorContext& context, const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous,
                Want want, Row* row) const;

  // Equation (1) with the coefficients of `errors` (the terms prepared for) and its derivatives, as
  // EvaluateJointErrorMap; `row` is the scratch (it holds phi afterwards; the gravity terms' derivatives
  // go into the joints' rows without a row per coefficient).
  void EvaluateMap(const JointErrors& errors, const JointErrorContext& context, const Eigen::VectorXd& qbar,
                   const Eigen::VectorXd* qbar_previous, JointErrorMap::Want want, Row* row,
                   JointErrorMap* out) const;

 private:
  // A gravity regressor: coefficient k, link frame j's origin (component -1) or axis `component`, against
  // the axis of frame axis_frame; slot: its joint's index in gravity_joints_.
  struct Gravity {
    int k, axis_frame, link, component, slot;
  };
  void GravityRows(const JointErrorContext& context, const Eigen::VectorXd& qbar, Want want, Row* row) const;
  void FillGravity(const Row& row, const Matrix6Xd& twists, const std::vector<int>& first, Eigen::MatrixXd* d) const;
  void ChainGravity(Row* row, const Matrix6Xd& twists, const std::vector<int>& first, Eigen::MatrixXd* dq) const;
  void OtherTerms(const JointErrorContext& context, const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous,
                  Want want, Row* row) const;

  std::vector<JointErrorTerm> terms_;  // the layout: types, joints, orders, keys
  std::vector<int> joint_first_, parameter_first_;  // the first frame each joint, each parameter moves
  std::vector<Gravity> gravity_;
  std::vector<int> gravity_joints_;  // the joints with gravity terms, in term order
  int first_limit_ = 0;              // the largest frame a gravity row depends on
  int num_coefficients_ = 0;
};

// The rest of EvaluateJointErrorMap once phi and its derivatives (null: not wanted) are known: q = qbar +
// C phi and the chain rule through the coefficients of `errors`.
void ChainJointErrorMap(const JointErrors& errors, const Eigen::VectorXd& qbar, const Eigen::VectorXd& phi,
                        const Eigen::MatrixXd* d_qbar, const Eigen::MatrixXd* d_previous,
                        const Eigen::MatrixXd* d_parameters, int num_parameters, JointErrorMap* out);

}  // namespace kincal
