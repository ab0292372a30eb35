#include "models/urdf_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kincal {
namespace {
constexpr int kRow = 9;  // x, y, z, roll, pitch, yaw, axis_azimuth, axis_tilt, offset
}

UrdfModel::UrdfModel(std::vector<JointType> joint_types) {
  using K = ParameterInfo::Kind;
  using G = ParameterInfo::Group;
  const int dof = static_cast<int>(joint_types.size());
  std::vector<ParameterInfo> info;
  std::vector<Op> ops;
  const std::vector<std::string> keys = RowKeys();
  for (int i = 0; i < dof; ++i) {
    const bool revolute = joint_types[i] == JointType::kRevolute;
    const int first = kRow * i;
    for (int k = 0; k < kRow; ++k) {
      const bool length = k < 3 || (k == 8 && !revolute);
      info.push_back(
          {keys[k] + "_" + std::to_string(i + 1), keys[k], length ? K::kLength : K::kAngle, G::kJoint, i + 1});
    }
    const int link = i + 1;
    ops.push_back({Op::kTx, first + 0, -1, link});
    ops.push_back({Op::kTy, first + 1, -1, link});
    ops.push_back({Op::kTz, first + 2, -1, link});
    ops.push_back({Op::kRz, first + 5, -1, link});
    ops.push_back({Op::kRy, first + 4, -1, link});
    ops.push_back({Op::kRx, first + 3, -1, link});
    // Rot(axis, q) = R_a Rz(q) R_a^T (or Trans(axis q) = R_a Tz(q) R_a^T).
    ops.push_back({Op::kRz, first + 6, -1, link});
    ops.push_back({Op::kRy, first + 7, -1, link});
    ops.push_back({revolute ? Op::kRz : Op::kTz, first + 8, i, link});
    ops.push_back({Op::kRy, first + 7, -1, link, -1.0});
    ops.push_back({Op::kRz, first + 6, -1, link, -1.0});
  }
  BuildChain(std::move(joint_types), std::move(info), std::move(ops));
}

Eigen::Isometry3d UrdfModel::JointOrigin(int i) const {
  const Eigen::VectorXd& v = Parameters();
  const int f = kRow * i;
  return PoseFromXyzRpy(v.segment<3>(f), v.segment<3>(f + 3));
}

Eigen::Vector3d UrdfModel::JointAxis(int i) const {
  const double azimuth = Parameters()[kRow * i + 6], tilt = Parameters()[kRow * i + 7];
  return {std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
}

Eigen::Vector2d UrdfModel::AxisAngles(const Eigen::Vector3d& axis) {
  const double norm = axis.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) throw std::invalid_argument("a joint axis must be a non-zero vector");
  const Eigen::Vector3d a = axis / norm;
  const double radial = std::hypot(a.x(), a.y());
  return {radial == 0.0 ? 0.0 : std::atan2(a.y(), a.x()), std::atan2(radial, a.z())};
}

void UrdfModel::SetJoint(int i, const Eigen::Isometry3d& T_parent_joint, const Eigen::Vector3d& axis) {
  Eigen::VectorXd v = Parameters();
  const int f = kRow * i;
  v.segment<3>(f) = T_parent_joint.translation();
  v.segment<3>(f + 3) = RpyFromRotation(T_parent_joint.linear());
  v.segment<2>(f + 6) = AxisAngles(axis);
  SetParameters(v);
}

}  // namespace kincal
