#include "models/poe_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kincal {

PoeModel::PoeModel(std::vector<JointType> joint_types) {
  using K = ParameterInfo::Kind;
  using G = ParameterInfo::Group;
  const int dof = static_cast<int>(joint_types.size());
  std::vector<ParameterInfo> info;
  std::vector<Op> ops;
  const char* keys[7] = {"x", "y", "z", "roll", "pitch", "yaw", "theta"};
  for (int i = 0; i < dof; ++i) {
    const int first = 7 * i;
    for (int k = 0; k < 7; ++k) {
      info.push_back({std::string(keys[k]) + "_" + std::to_string(i + 1), keys[k], k < 3 ? K::kLength : K::kAngle,
                      G::kJoint, i + 1});
    }
    const int link = i + 1;
    const bool revolute = joint_types[i] == JointType::kRevolute;
    ops.push_back({Op::kTx, first + 0, -1, link});
    ops.push_back({Op::kTy, first + 1, -1, link});
    if (revolute) ops.push_back({Op::kTz, first + 2, -1, link});
    ops.push_back({Op::kRz, first + 5, -1, link});
    ops.push_back({Op::kRy, first + 4, -1, link});
    ops.push_back({Op::kRx, first + 3, -1, link});
    // A prismatic joint slides along its own z axis: z_i is measured along it and the variable adds to it.
    if (!revolute) ops.push_back({Op::kTz, first + 2, i, link});
    ops.push_back({Op::kRz, first + 6, revolute ? i : -1, link});
  }
  BuildChain(std::move(joint_types), std::move(info), std::move(ops));
}

std::vector<Eigen::Isometry3d> PoeModel::JointFrames(const KinematicModel& model) {
  const int n = model.dof();
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(n);
  const Eigen::Isometry3d T_meas_tool = model.ForwardKinematics(q0);
  const Matrix6Xd J = model.JointJacobian(q0);
  // Joint frames J_i in the measurement frame: z along the joint axis, origin on it (for a revolute
  // joint, the foot of the perpendicular from the tool origin: v = omega x (p - o), so o = p + omega x v).
  std::vector<Eigen::Isometry3d> joint_frames;
  Eigen::Isometry3d previous = model.base();
  for (int i = 0; i < n; ++i) {
    const bool revolute = model.joint_type(i) == JointType::kRevolute;
    const Eigen::Vector3d z = (revolute ? J.col(i).tail<3>() : J.col(i).head<3>()).normalized();
    Eigen::Vector3d origin = previous.translation();
    if (revolute) {
      // The point of the axis nearest the previous frame's origin, so that rows stay short.
      const Eigen::Vector3d on_axis = T_meas_tool.translation() + z.cross(J.col(i).head<3>());
      origin = on_axis + z * z.dot(previous.translation() - on_axis);
    }
    // x: the previous frame's x made perpendicular to z (or y, if x is along z), for small angles.
    Eigen::Vector3d x = previous.linear().col(0) - z * z.dot(previous.linear().col(0));
    if (x.norm() < 1e-6) x = previous.linear().col(1) - z * z.dot(previous.linear().col(1));
    x.normalize();
    Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
    F.linear().col(0) = x;
    F.linear().col(1) = z.cross(x);
    F.linear().col(2) = z;
    F.translation() = origin;
    joint_frames.push_back(F);
    previous = F;
  }
  return joint_frames;
}

PoeModel PoeModel::FromModel(const KinematicModel& model) {
  const int n = model.dof();
  std::vector<JointType> types;
  for (int i = 0; i < n; ++i) types.push_back(model.joint_type(i));
  PoeModel poe(types);
  const Eigen::Isometry3d T_meas_tool = model.ForwardKinematics(Eigen::VectorXd::Zero(n));
  const std::vector<Eigen::Isometry3d> joint_frames = JointFrames(model);
  Eigen::VectorXd p = poe.Parameters();
  Eigen::Isometry3d parent = model.base();
  for (int i = 0; i < n; ++i) {
    const Eigen::Isometry3d T_rel = parent.inverse() * joint_frames[i];
    const Eigen::Vector3d rpy = RpyFromRotation(T_rel.linear());
    p.segment<3>(7 * i) = T_rel.translation();
    if (model.joint_type(i) == JointType::kPrismatic) {
      // z is measured along the joint axis: t = (x, y, 0) + z * R e_z.
      const double along = T_rel.linear()(2, 2);
      if (std::abs(along) < 1e-9)
        throw std::invalid_argument("PoeModel::FromModel: prismatic axis perpendicular to its parent's z");
      const double z = T_rel.translation().z() / along;
      p.segment<3>(7 * i) = T_rel.translation() - z * T_rel.linear().col(2);
      p[7 * i + 2] = z;
    }
    p[7 * i + 3] = rpy.x();
    p[7 * i + 4] = rpy.y();
    p[7 * i + 5] = rpy.z();
    p[7 * i + 6] = 0.0;
    parent = joint_frames[i];
  }
  poe.SetParameters(p);
  poe.SetBase(model.base());
  poe.SetTool(parent.inverse() * T_meas_tool);
  return poe;
}

}  // namespace kincal
