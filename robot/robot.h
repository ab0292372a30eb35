#pragma once
// Robot: everything a robot file describes. Geometry (a KinematicModel), optional drives, joint limits,
// markers on the tool and per-session bases, plus the units the file was written in (used only when
// the robot is written back).
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "framework/kinematic_model.h"
#include "framework/units.h"
#include "models/drive_model.h"
#include "models/joint_errors.h"
#include "robot/fixtures.h"

namespace kincal {

class Robot {
 public:
  Robot() = default;
  Robot(std::string name, std::unique_ptr<KinematicModel> model);
  // Copies deep-copy the model; every other member is a value, so a new member needs no copy code.
  Robot(const Robot& other) = default;
  Robot& operator=(const Robot& other) = default;
  Robot(Robot&&) = default;
  Robot& operator=(Robot&&) = default;

  // This robot (drives, limits, markers, ...) with another model of the same arm, e.g. the same
  // kinematics in another convention.
  Robot WithModel(std::unique_ptr<KinematicModel> model) const;

  std::string name;
  std::optional<DriveModel> drives;
  // Joint limits, rad (m for prismatic); empty means +-90 deg for every joint.
  std::vector<std::pair<double, double>> limits;
  // Marker (reflector) positions in the tool frame, m, by id (the dataset's `marker` column).
  std::map<std::string, Eigen::Vector3d> markers;
  // T_meas_base per session id (the dataset's `session` column), when the instrument was moved.
  std::map<int, Eigen::Isometry3d> session_bases;
  // Joint level (robot/joint_readings.h applies them, in this order):
  // actual angles = coupling x readings (row i: joint i as a combination of the controller's readings),
  // n x n, empty = identity; then the drives' ratio corrections; then the joint errors.
  Eigen::MatrixXd coupling;
  // Joint velocity limits, rad/s (m/s for prismatic joints); empty = not given. Approach terms need them.
  Eigen::VectorXd velocity_limits;
  // Direction of gravity in the base frame (unit); unset = -z of the base. Gravity terms use it.
  std::optional<Eigen::Vector3d> gravity;
  // Joint error terms, bound to the model (JointErrors::Bind) with their coefficients.
  JointErrors joint_errors;
  // Provenance of a robot imported from a URDF (kincal import): the file, the chain's end links and its
  // moving joints. `kincal convert --to urdf` then edits that file's joint numbers and keeps the rest.
  struct UrdfSource {
    std::string path, base_link, tip_link;
    std::vector<std::string> joints;
  };
  std::optional<UrdfSource> urdf;
  // Pivots, planes and points the dataset's other instruments measure against (robot/fixtures.h).
  Fixtures fixtures;
  Unit length_unit = {"mm", 1e-3};
  Unit angle_unit = {"deg", M_PI / 180.0};

  KinematicModel& model() { return *model_; }
  const KinematicModel& model() const { return *model_; }
  bool has_model() const { return static_cast<bool>(model_); }
  int dof() const { return model_ ? model_->dof() : 0; }

  // Limits in effect (the default when none were given).
  std::pair<double, double> Limit(int joint) const;
  // Position of marker `id` in the tool frame; the tool origin for "" (no marker column).
  // Throws std::invalid_argument for an unknown id.
  Eigen::Vector3d MarkerPosition(const std::string& id) const;
  // T_meas_base for a session (the model's base for session 0 or a session without its own base).
  Eigen::Isometry3d SessionBase(int session) const;
  // The unit gravity direction in the base frame (default -z).
  Eigen::Vector3d GravityDirection() const;
  // Throws std::invalid_argument unless the joint-level members fit the model: coupling n x n, finite and
  // invertible; velocity limits n positive numbers; gravity a non-zero finite vector; joint errors bound
  // (Bind) to this model, with velocity limits when approach terms are present.
  void ValidateJointLevel() const;

 private:
  // Owns the model; copying clones it.
  class ModelPtr {
   public:
    ModelPtr() = default;
    explicit ModelPtr(std::unique_ptr<KinematicModel> p) : p_(std::move(p)) {}
    ModelPtr(const ModelPtr& o) : p_(o.p_ ? o.p_->Clone() : nullptr) {}
    ModelPtr& operator=(const ModelPtr& o) {
      if (this != &o) p_ = o.p_ ? o.p_->Clone() : nullptr;
      return *this;
    }
    ModelPtr(ModelPtr&&) = default;
    ModelPtr& operator=(ModelPtr&&) = default;
    KinematicModel& operator*() const { return *p_; }
    explicit operator bool() const { return p_ != nullptr; }
    KinematicModel* operator->() const { return p_.get(); }

   private:
    std::unique_ptr<KinematicModel> p_;
  };
  ModelPtr model_;
};

// Moves each revolute joint of q by whole turns into the robot's limits, to the representative nearest
// `reference`'s joint (null: nearest q's own value); a joint that no turn brings inside goes to the
// representative nearest its limits. A joint (any type) within `slack` (rad or m) outside a limit, a
// solution on the limit to rounding, is clamped onto it and *clamped set. True when every joint ends
// inside. The inverse kinematics, the compensators and their restarts all place joints this one way.
bool WrapIntoLimits(const Robot& robot, const Eigen::VectorXd* reference, Eigen::Ref<Eigen::VectorXd> q,
                    double slack = 0.0, bool* clamped = nullptr);

}  // namespace kincal
