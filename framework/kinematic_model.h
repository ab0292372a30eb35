#pragma once
// KinematicModel: the geometry of a serial arm with named, maskable parameters.
//
// Every model maps actual joint angles q (rad; metres for prismatic joints) to the pose of the tool in
// the measurement frame:  T_meas_tool(q) = T_meas_base * T_base_n(q) * T_n_tool.
// Base and tool are parameters like the link geometry (base_x .. base_yaw, tool_x .. tool_yaw, xyz then
// roll-pitch-yaw about fixed axes, R = Rz(yaw) Ry(pitch) Rx(roll)), so estimators treat all alike.
//
// Jacobian layout, shared by JointJacobian and ParameterJacobian: 6 rows, rows 0-2 the derivative of the
// position of a point fixed in the tool frame, rows 3-5 the angular velocity omega of the tool in the
// measurement frame, dR/dx = [omega]x R. Both are analytic and tested against central differences.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/math.h"

namespace kincal {

enum class JointType { kRevolute, kPrismatic };

struct ParameterInfo {
  enum class Kind { kLength, kAngle };
  enum class Group { kJoint, kBase, kTool };
  std::string name;  // "alpha_2", "base_x", "tool_yaw", ...
  std::string key;   // the robot-file key: "alpha", "x", "yaw", ...
  Kind kind = Kind::kLength;
  Group group = Group::kJoint;
  int joint = 0;  // 1-based joint (row) index for Group::kJoint, 0 otherwise
};

class KinematicModel {
 public:
  virtual ~KinematicModel() = default;
  virtual std::unique_ptr<KinematicModel> Clone() const = 0;

  // "mdh", "dh", ...: the robot file's `convention`.
  virtual std::string convention() const = 0;
  int dof() const { return static_cast<int>(joint_types_.size()); }
  JointType joint_type(int i) const { return joint_types_[i]; }
  // Per-row keys the robot file uses for this convention, e.g. {"alpha", "a", "theta", "d"}.
  virtual std::vector<std::string> RowKeys() const = 0;
  // Index (0..n, into FramePoses) of the frame whose z axis is joint `joint`'s (0-based) axis, with its
  // origin on that axis, and which joints 1..joint-1 (not joint itself) move rigidly: joint + 1 for MDH,
  // Hayati and local POE (the joint turns its own frame about its z), joint for standard DH (the joint
  // turns about the previous frame's z). -1 when the convention has no such frame; joint-level gravity
  // terms (models/joint_errors.h) need one.
  virtual int JointAxisFrame(int joint) const {
    (void)joint;
    return -1;
  }

  // ---- Parameters -------------------------------------------------------------------------------
  int num_parameters() const { return static_cast<int>(info_.size()); }
  const std::vector<ParameterInfo>& parameter_info() const { return info_; }
  std::vector<std::string> ParameterNames() const;
  const Eigen::VectorXd& Parameters() const { return values_; }
  void SetParameters(const Eigen::VectorXd& values);
  // Index of a named parameter; throws std::invalid_argument listing the names if unknown.
  int ParameterIndex(const std::string& name) const;
  // -1 if unknown.
  int FindParameter(const std::string& name) const;
  double Parameter(const std::string& name) const { return values_[ParameterIndex(name)]; }
  void SetParameter(const std::string& name, double value);

  // Free/fixed mask: estimators optimise the free subset only. All free by default.
  const std::vector<bool>& FreeMask() const { return free_; }
  void SetFree(const std::string& name, bool free) { free_[ParameterIndex(name)] = free; }
  void SetFreeMask(const std::vector<bool>& mask);
  // Why parameter `index` is redundant with the others at the model's current values (an estimator
  // holds it at its value), or "" when it is not. Conventions whose parameters are independent by
  // construction keep the default.
  virtual std::string RedundantParameterReason(int index) const {
    (void)index;
    return "";
  }

  Eigen::Isometry3d base() const;  // T_meas_base (frame 0 in the measurement frame)
  Eigen::Isometry3d tool() const;  // T_n_tool
  void SetBase(const Eigen::Isometry3d& T_meas_base);
  void SetTool(const Eigen::Isometry3d& T_n_tool);

  // ---- Kinematics --------------------------------------------------------------------------------
  // T_meas_tool(q).
  virtual Eigen::Isometry3d ForwardKinematics(const Eigen::VectorXd& q) const = 0;
  // T_meas_frame_i for i = 0..n (frame 0 = base), then T_meas_tool: n + 2 poses.
  virtual std::vector<Eigen::Isometry3d> FramePoses(const Eigen::VectorXd& q) const = 0;
  // 6 x n geometric Jacobian of the point p_tool_point (tool frame) and of the tool orientation.
  virtual Matrix6Xd JointJacobian(const Eigen::VectorXd& q,
                                  const Eigen::Vector3d& p_tool_point = Eigen::Vector3d::Zero()) const = 0;
  // dT_meas_tool/dq_i as 4x4 matrices (the seed's eq. 11: T_0^{i-1} dT_{i-1}^i/dq_i T_i^h), i = 1..n.
  virtual std::vector<Eigen::Matrix4d> PoseDerivatives(const Eigen::VectorXd& q) const = 0;
  // 6 x p Jacobian of the point p_tool_point and of the tool orientation with respect to every
  // parameter (free or not), in ParameterNames() order. Writes into *J (resized if needed) and returns
  // T_meas_tool(q) as a by-product, so estimators get pose and derivatives from one pass.
  virtual Eigen::Isometry3d ParameterJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& p_tool_point,
                                              Matrix6Xd* J) const = 0;
  Matrix6Xd ParameterJacobian(const Eigen::VectorXd& q) const;

 protected:
  // Subclasses declare their joints and parameters once, in their constructor.
  void Declare(std::vector<JointType> joint_types, std::vector<ParameterInfo> info);
  // Called after any parameter change, so subclasses can refresh cached constant transforms.
  virtual void OnParametersChanged() {}

 private:
  std::vector<JointType> joint_types_;
  std::vector<ParameterInfo> info_;
  Eigen::VectorXd values_;
  std::vector<bool> free_;
  int base_index_ = -1;  // index of base_x; the six base parameters are contiguous
  int tool_index_ = -1;
};

}  // namespace kincal
