#include "models/chain_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kincal {
namespace {

bool IsRotation(ChainModel::Op::Type t) { return t >= ChainModel::Op::kRx; }
int AxisOf(ChainModel::Op::Type t) { return static_cast<int>(t) % 3; }

std::vector<ParameterInfo> PoseParameters(const std::string& prefix, ParameterInfo::Group group) {
  using K = ParameterInfo::Kind;
  std::vector<ParameterInfo> out;
  const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  for (int i = 0; i < 6; ++i) {
    out.push_back({prefix + "_" + keys[i], keys[i], i < 3 ? K::kLength : K::kAngle, group, 0});
  }
  return out;
}

}  // namespace

void ChainModel::BuildChain(std::vector<JointType> joint_types, std::vector<ParameterInfo> joint_parameters,
                            std::vector<Op> link_ops) {
  const int n = static_cast<int>(joint_types.size());
  const int p_joint = static_cast<int>(joint_parameters.size());
  std::vector<ParameterInfo> info = std::move(joint_parameters);
  for (auto& p : PoseParameters("base", ParameterInfo::Group::kBase)) info.push_back(p);
  for (auto& p : PoseParameters("tool", ParameterInfo::Group::kTool)) info.push_back(p);
  Declare(std::move(joint_types), std::move(info));

  // Pose ops: Trans(x, y, z) * Rz(yaw) * Ry(pitch) * Rx(roll).
  auto pose_ops = [](int first, int link) {
    return std::vector<Op>{{Op::kTx, first, -1, link},     {Op::kTy, first + 1, -1, link},
                           {Op::kTz, first + 2, -1, link}, {Op::kRz, first + 5, -1, link},
                           {Op::kRy, first + 4, -1, link}, {Op::kRx, first + 3, -1, link}};
  };
  ops_ = pose_ops(p_joint, 0);
  for (const Op& op : link_ops) ops_.push_back(op);
  for (const Op& op : pose_ops(p_joint + 6, n + 1)) ops_.push_back(op);

  joint_ops_.clear();
  for (const Op& op : ops_) {
    if (op.joint >= 0) {
      if (op.scale != 1.0) throw std::logic_error("ChainModel: a joint op must have scale 1");
      if (op.joint != static_cast<int>(joint_ops_.size())) {
        throw std::logic_error("ChainModel: joint ops must appear once each, in order");
      }
      joint_ops_.push_back(op);
    }
  }
  if (static_cast<int>(joint_ops_.size()) != n) throw std::logic_error("ChainModel: missing joint op");
  OnParametersChanged();
}

inline void ChainModel::Apply(Op::Type type, double value, double c, double s, Frame* F) {
  Eigen::Matrix3d& R = F->R;
  switch (type) {
    case Op::kTx:
      F->p += R.col(0) * value;
      break;
    case Op::kTy:
      F->p += R.col(1) * value;
      break;
    case Op::kTz:
      F->p += R.col(2) * value;
      break;
    case Op::kRx: {
      const Eigen::Vector3d y = R.col(1);
      R.col(1) = y * c + R.col(2) * s;
      R.col(2) = R.col(2) * c - y * s;
      break;
    }
    case Op::kRy: {
      const Eigen::Vector3d x = R.col(0);
      R.col(0) = x * c - R.col(2) * s;
      R.col(2) = x * s + R.col(2) * c;
      break;
    }
    case Op::kRz: {
      const Eigen::Vector3d x = R.col(0);
      R.col(0) = x * c + R.col(1) * s;
      R.col(1) = R.col(1) * c - x * s;
      break;
    }
  }
}

void ChainModel::OnParametersChanged() {
  const Eigen::VectorXd& v = Parameters();
  cos_.resize(ops_.size());
  sin_.resize(ops_.size());
  for (size_t k = 0; k < ops_.size(); ++k) {
    cos_[k] = std::cos(ops_[k].scale * v[ops_[k].parameter]);
    sin_[k] = std::sin(ops_[k].scale * v[ops_[k].parameter]);
  }
  steps_.clear();
  for (size_t k = 0; k < ops_.size(); ++k) {
    const Op& op = ops_[k];
    const double value = op.scale * v[op.parameter];
    // Translating or turning by exactly zero changes no bit of the frame; such ops are skipped.
    if (op.joint < 0 && value == 0.0) continue;
    steps_.push_back({op.type, op.joint, value, cos_[k], sin_[k]});
  }
}

namespace {
[[noreturn]] void ThrowJointCount(int expected, Eigen::Index got) {
  throw std::invalid_argument("expected " + std::to_string(expected) + " joint values, got " + std::to_string(got));
}
}  // namespace

inline void ChainModel::CheckJoints(const Eigen::VectorXd& q) const {
  if (q.size() != dof()) ThrowJointCount(dof(), q.size());
}

Eigen::Isometry3d ChainModel::ForwardKinematics(const Eigen::VectorXd& q) const {
  CheckJoints(q);
  Frame F;
  for (const Step& step : steps_) {
    if (step.joint < 0) {
      Apply(step.type, step.value, step.c, step.s, &F);
    } else {
      const double value = step.value + q[step.joint];
      Apply(step.type, value, std::cos(value), std::sin(value), &F);
    }
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = F.R;
  T.translation() = F.p;
  return T;
}

std::vector<Eigen::Isometry3d> ChainModel::FramePoses(const Eigen::VectorXd& q) const {
  CheckJoints(q);
  const Eigen::VectorXd& v = Parameters();
  std::vector<Eigen::Isometry3d> poses(dof() + 2, Eigen::Isometry3d::Identity());
  Frame F;
  for (size_t k = 0; k < ops_.size(); ++k) {
    const Op& op = ops_[k];
    const double value = op.scale * v[op.parameter] + (op.joint >= 0 ? q[op.joint] : 0.0);
    Apply(op.type, value, std::cos(value), std::sin(value), &F);
    const bool link_ends = k + 1 == ops_.size() || ops_[k + 1].link != op.link;
    if (link_ends) {
      poses[op.link].linear() = F.R;
      poses[op.link].translation() = F.p;
    }
  }
  return poses;
}

Matrix6Xd ChainModel::JointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point) const {
  Frame F;
  Matrix6Xd J;
  JacobianAndTool(q, p_tool_point, &F, &J);
  return J;
}

void ChainModel::JacobianAndTool(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point, Frame* tool,
                                 Matrix6Xd* J_out) const {
  CheckJoints(q);
  Matrix6Xd& J = *J_out;
  J.resize(6, dof());
  Frame& F = *tool;
  F = Frame();
  for (const Step& step : steps_) {
    if (step.joint < 0) {
      Apply(step.type, step.value, step.c, step.s, &F);
      continue;
    }
    const Eigen::Vector3d axis = F.R.col(AxisOf(step.type));
    auto column = J.col(step.joint);
    if (IsRotation(step.type)) {
      // omega x (p_end - o): the omega x p_end part is added once p_end is known.
      column.head<3>() = -axis.cross(F.p);
      column.tail<3>() = axis;
    } else {
      column.head<3>() = axis;
      column.tail<3>().setZero();
    }
    const double value = step.value + q[step.joint];
    Apply(step.type, value, std::cos(value), std::sin(value), &F);
  }
  const Eigen::Vector3d p_end = F.p + F.R * p_tool_point;
  J.topRows<3>().noalias() -= Skew(p_end) * J.bottomRows<3>();  // disjoint rows: no temporary
}

Eigen::Isometry3d ChainModel::JointJacobianAndPose(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                                   Matrix6Xd* J) const {
  Frame tool;
  JacobianAndTool(q, p_tool_point, &tool, J);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = tool.R;
  T.translation() = tool.p;
  return T;
}

Eigen::Isometry3d PoseAndJointJacobian(const KinematicModel& model, const Eigen::VectorXd& q, Matrix6Xd* J,
                                       const Eigen::Vector3d& p_tool_point) {
  if (const auto* chain = dynamic_cast<const ChainModel*>(&model)) return chain->JointJacobianAndPose(q, p_tool_point, J);
  *J = model.JointJacobian(q, p_tool_point);
  return model.ForwardKinematics(q);
}

std::vector<Eigen::Matrix4d> ChainModel::PoseDerivatives(const Eigen::VectorXd& q) const {
  Frame tool;
  Matrix6Xd J;
  JacobianAndTool(q, Eigen::Vector3d::Zero(), &tool, &J);  // one pass: J and R_meas_tool
  const Eigen::Matrix3d& R = tool.R;
  std::vector<Eigen::Matrix4d> dT(dof(), Eigen::Matrix4d::Zero());
  for (int i = 0; i < dof(); ++i) {
    dT[i].topLeftCorner<3, 3>() = Skew(J.col(i).tail<3>()) * R;
    dT[i].topRightCorner<3, 1>() = J.col(i).head<3>();
  }
  return dT;
}

Eigen::Isometry3d ChainModel::ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                                Matrix6Xd* J) const {
  CheckJoints(q);
  const Eigen::VectorXd& v = Parameters();
  J->setZero(6, num_parameters());
  Frame F;
  for (size_t k = 0; k < ops_.size(); ++k) {
    const Op& op = ops_[k];
    const Eigen::Vector3d axis = F.R.col(AxisOf(op.type));
    auto column = J->col(op.parameter);
    double value = op.scale * v[op.parameter], c = cos_[k], s = sin_[k];
    if (op.joint >= 0) {
      value += q[op.joint];
      c = std::cos(value);
      s = std::sin(value);
    }
    // += and scale: a parameter that drives several ops collects each op's share (chain rule).
    if (IsRotation(op.type)) {
      column.head<3>() -= op.scale * axis.cross(F.p);
      column.tail<3>() += op.scale * axis;
    } else {
      column.head<3>() += op.scale * axis;
    }
    Apply(op.type, value, c, s, &F);
  }
  const Eigen::Vector3d p_end = F.p + F.R * p_tool_point;
  J->topRows<3>() -= Skew(p_end) * J->bottomRows<3>();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = F.R;
  T.translation() = F.p;
  return T;
}

}  // namespace kincal
