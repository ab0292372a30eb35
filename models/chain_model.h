#pragma once
// ChainModel: a KinematicModel written as a product of elementary transforms (translations and rotations
// about the local x, y or z axis), each driven by one parameter and, for the joint's own transform, by
// the joint variable as well. MDH, DH and Hayati are all such products; writing them this way gives one
// implementation of forward kinematics and of every analytic derivative:
//   a rotation about the local axis w (world direction omega, at world point o) moves a tool point p
//   with velocity omega x (p - o) and turns the tool with angular velocity omega;
//   a translation along w moves every tool point with velocity omega and does not turn it.
// Forward kinematics and the joint Jacobian walk the elementary ops themselves, with the cosines and sines
// of the constant ones computed when the parameters change and the ops that are exactly the identity (a
// zero offset or angle, common in DH tables) left out: a rotation about a local axis mixes two columns of
// the running frame (12 multiplications), a translation adds one column (3), less than composing dense
// 3x4 blocks (36), so each joint costs one sincos and a few dozen multiplications.
#include <vector>

#include "framework/kinematic_model.h"

namespace kincal {

class ChainModel : public KinematicModel {
 public:
  struct Op {
    enum Type { kTx, kTy, kTz, kRx, kRy, kRz };
    Type type = kTx;
    int parameter = -1;  // index into Parameters()
    int joint = -1;      // 0-based joint whose variable is added to the parameter, -1 if none
    int link = 0;        // 0 = base, 1..n = link i (ends at frame i), n + 1 = tool
    // The op turns or moves by scale * parameter (joint ops: parameter + q, scale 1). A parameter may
    // drive several ops (URDF's axis: R_a Rz(q) R_a^T uses its angles twice, once with scale -1).
    double scale = 1.0;
  };

  Eigen::Isometry3d ForwardKinematics(const Eigen::VectorXd& q) const override;
  std::vector<Eigen::Isometry3d> FramePoses(const Eigen::VectorXd& q) const override;
  Matrix6Xd JointJacobian(const Eigen::VectorXd& q,
                          const Eigen::Vector3d& p_tool_point = Eigen::Vector3d::Zero()) const override;
  std::vector<Eigen::Matrix4d> PoseDerivatives(const Eigen::VectorXd& q) const override;
  Eigen::Isometry3d ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                      Matrix6Xd* J) const override;
  using KinematicModel::ParameterJacobian;

  const std::vector<Op>& ops() const { return ops_; }

  // JointJacobian and T_meas_tool(q) from its one pass (the tool frame is where it ends): the pose to
  // the bit of ForwardKinematics, the Jacobian of JointJacobian. *J resized if needed.
  Eigen::Isometry3d JointJacobianAndPose(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                         Matrix6Xd* J) const;

 protected:
  // Declares base ops, the subclass's link ops and tool ops. Subclasses call this from their constructor.
  void BuildChain(std::vector<JointType> joint_types, std::vector<ParameterInfo> joint_parameters,
                  std::vector<Op> link_ops);
  void OnParametersChanged() override;

 private:
  struct Frame {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
  };
  // One op of the fast path: a constant op with its value, cosine and sine, or a joint op, whose value is
  // the parameter the joint variable adds to.
  struct Step {
    Op::Type type = Op::kTx;
    int joint = -1;
    double value = 0.0, c = 1.0, s = 0.0;
  };
  static void Apply(Op::Type type, double value, double c, double s, Frame* F);
  // JointJacobian into *J (its storage reused), also giving the tool frame T_meas_tool(q) it passes through.
  void JacobianAndTool(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point, Frame* tool, Matrix6Xd* J) const;
  void CheckJoints(const Eigen::VectorXd& q) const;

  std::vector<Op> ops_;
  std::vector<Step> steps_;        // ops_ without the exact identities, for the current parameters
  std::vector<Op> joint_ops_;      // one per joint, in order
  std::vector<double> cos_, sin_;  // of each op's parameter value (joint ops: of the parameter alone)
};

// T_meas_tool(q) and, into *J, the joint Jacobian of the tool point: one pass for a chain model
// (ChainModel::JointJacobianAndPose), ForwardKinematics and JointJacobian for any other.
Eigen::Isometry3d PoseAndJointJacobian(const KinematicModel& model, const Eigen::VectorXd& q, Matrix6Xd* J,
                                       const Eigen::Vector3d& p_tool_point = Eigen::Vector3d::Zero());

}  // namespace kincal
