#pragma once
// Local product-of-exponentials model (Chen, Yang & Lim 2001, "Local POE model for robot kinematic
// calibration"; the singularity-free alternative METHOD.md section 2 asks for). Each row is the full
// pose of joint i's frame in joint i-1's frame at q = 0, and the joint turns (or slides) about that
// frame's z axis:
//     T_{i-1}^{i}(q_i) = Trans(x_i, y_i, z_i) * Rz(yaw_i) * Ry(pitch_i) * Rx(roll_i) * Rz(theta_i + q_i)
// (a prismatic row: Trans(x_i, y_i, 0) * Rz Ry Rx * Dz(z_i + q_i) * Rz(theta_i), sliding along its own z).
// Unlike (M)DH, any placement of consecutive axes, parallel ones included, has a nearby well-conditioned
// representation. The price is redundancy: 7 numbers per row where 4 (or 6 with the base) suffice; the
// estimators' identifiability analysis fixes the redundant ones (theta_i against yaw_i, translation
// along the axis against the next row).
#include "models/chain_model.h"

namespace kincal {

class PoeModel final : public ChainModel {
 public:
  explicit PoeModel(std::vector<JointType> joint_types);
  explicit PoeModel(int revolute_joints) : PoeModel(std::vector<JointType>(revolute_joints, JointType::kRevolute)) {}
  std::unique_ptr<KinematicModel> Clone() const override { return std::make_unique<PoeModel>(*this); }
  std::string convention() const override { return "poe"; }
  int JointAxisFrame(int joint) const override { return joint + 1; }
  std::vector<std::string> RowKeys() const override { return {"x", "y", "z", "roll", "pitch", "yaw", "theta"}; }

  // The local POE model with the same forward kinematics as `model` for every q (any convention):
  // joint frames are placed on the joint axes of `model` at q = 0, base and tool carried over.
  static PoeModel FromModel(const KinematicModel& model);
  // The joint frames FromModel places, in the measurement frame at q = 0: z along each joint axis, the
  // origin on it (a revolute axis: its point nearest the previous frame's origin; a prismatic joint:
  // the previous frame's origin), x the previous frame's x made perpendicular to z.
  static std::vector<Eigen::Isometry3d> JointFrames(const KinematicModel& model);
};

}  // namespace kincal
