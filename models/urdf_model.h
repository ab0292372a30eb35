#pragma once
// The URDF convention (ROS REP 103/120; urdf/XML/joint): a joint is a rigid `origin` (xyz, then
// roll-pitch-yaw about fixed axes) from its parent link's frame, followed by a motion about or along a
// unit `axis` given in that joint frame. The child link's frame is the joint frame after the motion:
//     T_{i-1}^{i}(q_i) = Trans(x_i, y_i, z_i) * Rz(yaw_i) * Ry(pitch_i) * Rx(roll_i) * Rot(axis_i, offset_i + q_i)
// (a prismatic joint: Trans(axis_i * (offset_i + q_i)) instead of the rotation).
// The axis is two angles, axis_i = Rz(axis_azimuth_i) * Ry(axis_tilt_i) * e_z
//   = (sin tilt cos azimuth, sin tilt sin azimuth, cos tilt),
// and the motion is written as R_a * Rz(q) * R_a^T with R_a = Rz(azimuth) Ry(tilt), so every factor is
// an elementary op of ChainModel (the axis angles drive two ops each, the second with scale -1).
// offset_i is a joint zero offset that URDF has no field for (0 on import; folded into the origin on
// export). 9 numbers per joint where 4 suffice between consecutive axes: the redundant ones (the axis
// against the origin's rpy, the offset against the rpy, the azimuth of an axis along z, translations
// along the axis) are held by the estimators' identifiability analysis, as for POE.
#include "models/chain_model.h"

namespace kincal {

class UrdfModel final : public ChainModel {
 public:
  explicit UrdfModel(std::vector<JointType> joint_types);
  explicit UrdfModel(int revolute_joints) : UrdfModel(std::vector<JointType>(revolute_joints, JointType::kRevolute)) {}
  std::unique_ptr<KinematicModel> Clone() const override { return std::make_unique<UrdfModel>(*this); }
  std::string convention() const override { return "urdf"; }
  std::vector<std::string> RowKeys() const override {
    return {"x", "y", "z", "roll", "pitch", "yaw", "axis_azimuth", "axis_tilt", "offset"};
  }
  // No frame of this convention has the joint axis as its z axis in general (the child link's frame is
  // URDF's, the axis any direction in it), so joint-level gravity terms need another convention.

  // Joint i's (0-based) origin T_parent_joint (offset not included) and unit axis in the joint frame.
  Eigen::Isometry3d JointOrigin(int i) const;
  Eigen::Vector3d JointAxis(int i) const;
  // Sets joint i's origin and axis (the axis normalised; azimuth 0 for an axis along +-z).
  void SetJoint(int i, const Eigen::Isometry3d& T_parent_joint, const Eigen::Vector3d& axis);
  // Axis angles of a direction: (azimuth, tilt).
  static Eigen::Vector2d AxisAngles(const Eigen::Vector3d& axis);
};

}  // namespace kincal
