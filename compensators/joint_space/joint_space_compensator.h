#pragma once
// Joint-space compensation: a smooth expansion of the identified robot's pose in its joints, built
// offline, and at run time a fixed number of Jacobian steps from the controller's nominal solution, with
// no iteration to convergence and no model evaluation.
//
// What is fitted. Any rigid serial chain factors exactly as the product of exponentials (Murray, Li and
// Sastry 1994, eq. 3.3; Brockett 1984)
//     T_meas_tool(q) = X_1(q_1) X_2(q_2) ... X_n(q_n) T(0),   X_j(q_j) = T(0, .., q_j, .., 0) T(0)^-1,
// X_j being the motion of joint j (a rotation about, or a translation along, its axis at q = 0) in the
// measurement frame. Base and tool, however far (a tracker 1.5 m away, a marker 120 mm off the
// flange), are absorbed exactly in T(0) and in the axes, so each joint enters through one factor of its
// own, and no joint needs a grid: each X_j is fitted by linear least squares as a Fourier series in q_j
// (pose_expansion.h), of degree 1 exact (3 x 12 numbers per joint, 1.8 KB for a 6-joint arm), with no
// resolution to choose and no singular configuration to avoid. Prepare() checks the product against
// the model at random configurations and refuses it beyond `max_fit_error` (a model that is not a rigid
// chain). A tensor series over the inner joints (the pose as one function of q_2..q_5, 81 terms) was
// tried first: exact too, but slower to evaluate with its Jacobian.
//
// At run time, from the seed q_0 (the controller's nominal solution, where the nominal robot reaches the
// target T) plus a constant offset c, `steps` damped Gauss-Newton steps (a fixed count: no convergence
// test decides to go on, no line search):
//     dq = (J^T W J + mu I)^-1 J^T W e,   e = PoseError(T_id(q), T),   J = dT_id/dq from the expansion,
// W dividing position rows by length_scale. The first step corrects the pose error of the identified
// robot against the nominal one at the seed. c is the joint-wise median of the exact corrections at 100
// random well-conditioned configurations, solved offline (the part of the correction common to all
// configurations: joint zero offsets, base rotation about axis 1); it shortens the first step a little
// (median error after one step 0.21 mm instead of 0.30 mm on the tracked seed arm). The error left after
// a step is quadratic in the step, but on the seed's arm the correction is large over much of the joint
// space (median 0.07 rad, 10 % above 0.25 rad: its wrist is near-singular there), hence 3 steps by
// default: 2 leave 83 % of random targets within 0.05 mm and 1e-4 rad, 3 leave 97 %, 4 leave 99.5 %.
// Status: kConverged when the identified model's pose at the result (the forward kinematics Compensate()
// computes for the report) is within the tolerances; otherwise kSingular when a step was cut to max_step
// (near a singular configuration the correction is large) or the steps stopped where sigma_min / sigma_max
// of the identified arm's weighted Jacobian is below singular_ratio (the iterative compensators' test,
// compensators/common/gauss_newton.h: the same word for the same place); kIterationLimit otherwise;
// kFailed when a prismatic joint leaves the range its factor was fitted over. Accuracy, speed and
// memory: compensators/README.md (tests/compensators/joint_space_accuracy_test.cc,
// bench/compensators_bench.cc).
#include <string>
#include <vector>

#include "compensators/joint_space/pose_expansion.h"
#include "compensators/compensator.h"

namespace kincal {

class Rng;

class JointSpaceCompensator final : public Compensator {
 public:
  struct Options {
    // Degree of the series in each joint: 1 is exact for rigid chains; higher only for models that are
    // not (memory 12 (2 degree + 1) doubles per joint).
    int degree = 1;
    // Jacobian steps at run time (a fixed count; no convergence test decides to go on), 1 to 5.
    int steps = 3;
    // m: position rows are divided by it, so 1 mm weighs like 2 mrad at the default 0.5 m (the arm's reach).
    double length_scale = 0.5;
    // Levenberg damping mu = damping^2 (weighted units): negligible where sigma_min >> damping, keeps
    // the step finite at singular configurations and gives position-only targets the minimum-norm step.
    double damping = 1e-6;
    // rad: the longest step (Euclidean norm); longer ones are scaled down and reported kSingular.
    double max_step = 0.5;
    // A target left off the tolerances where sigma_min / sigma_max of the identified arm's Jacobian
    // (position rows divided by length_scale) is below this is reported kSingular, as the iterative
    // compensators do (their default singular_ratio). Only computed for such targets. 0: only cut steps.
    double singular_ratio = 1e-3;
    // m and rad: kConverged when the final pose (by the expansion) is within both.
    double position_tolerance = 1e-6;
    double orientation_tolerance = 1e-6;
    // m (rad for the rotation entries): Prepare() throws when the expansion misses the model by more
    // at random configurations (a model that is not a rigid chain needs a higher degree).
    double max_fit_error = 1e-9;
    // Refuse expansions larger than this (bytes).
    double max_table_bytes = 5e7;

    // Every key, its default, doc and requirement (framework/options.h).
    static const OptionTable<Options>& Table();
    bool IsValid(std::string* why) const;
    static Options FromYaml(const YAML::Node& node);
  };

  // What Prepare() built.
  struct TableInfo {
    int factors = 0;  // one per joint
    int terms = 0;    // per factor
    size_t memory_bytes = 0;
    double fit_position_error = 0.0;     // m, largest over the check configurations
    double fit_orientation_error = 0.0;  // largest rotation-entry difference
    int offset_samples = 0;              // configurations the offset is the median over
    double build_seconds = 0.0;
  };

  JointSpaceCompensator();
  explicit JointSpaceCompensator(const Options& options) : options_(options) {}
  std::string name() const override { return "joint_space"; }
  const Options& options() const { return options_; }
  const TableInfo& table_info() const { return info_; }

  static constexpr int kMaxJoints = 16;
  using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxJoints>;
  using Joints = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;

  // The identified robot's pose by the expansion (and, when J is not null, its 6 x n Jacobian in the
  // model's layout: point velocity, then angular velocity, both in the measurement frame). False when a
  // prismatic joint is outside its fitted range.
  bool Pose(const Joints& q, Eigen::Isometry3d* T_meas_tool, Jacobian* J = nullptr) const;

  // cos and sin of each joint angle, updated across the steps of one lookup: after a step dq the new
  // values follow from the angle-addition formulas with cos(dq), sin(dq) from their Taylor series, which
  // costs a fraction of a libm call (sin and cos were a quarter of a lookup's instructions).
  struct JointTrig {
    double c[kMaxJoints], s[kMaxJoints];
    void Set(const Joints& q);
    void Advance(const Joints& dq);  // q += dq
  };
  // Pose() on the fast path, with the joints' cos and sin given.
  bool Pose(const Joints& q, const JointTrig& trig, Eigen::Isometry3d* T_meas_tool, Jacobian* J) const;
  // The same for six joints with fixed sizes: the pose and its 6 x 6 Jacobian.
  void PoseJacobian6(const JointTrig& trig, Eigen::Isometry3d* T_meas_tool, Eigen::Matrix<double, 6, 6>* J) const;
  // rad: the typical correction added to every seed before the first step (see above).
  const Eigen::VectorXd& offset() const { return offset_; }

 private:
  void DoPrepare() override;
  // Prepare()'s last parts: the expansion measured against the model at random configurations of `rng`
  // (throws beyond max_fit_error), then the common correction offset_ from the same stream.
  void MeasureFit(Rng* rng);
  void FitOffset(Rng* rng);
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override;
  // `steps` damped Gauss-Newton steps towards `target` from *q; *cut tells whether one was shortened.
  bool Steps(const CompensationTarget& target, int steps, Joints* q, bool* cut) const;
  void JudgeErrors(const CompensationTarget& target, CompensationResult* result) const override;
  // sigma_min / sigma_max of the expansion's Jacobian at q (the identified arm's to 1e-9), in the target's
  // rows, position rows divided by length_scale, below singular_ratio.
  bool NearSingular(const CompensationTarget& target, const Eigen::VectorXd& q) const;
  // Prismatic joints within the ranges their factors were fitted over.
  bool InsideFittedRanges(const Joints& q) const;

  // X_j = c0 + cos(q_j) c1 + sin(q_j) c2: the fast path for all-revolute chains of degree 1.
  struct RevoluteFactor {
    PoseExpansion::Pose34 c0, c1, c2;
  };

  Options options_;
  std::vector<PoseExpansion> factors_;                    // X_j(q_j)
  std::vector<RevoluteFactor> revolute_;                  // the same as RevoluteFactor when they apply, else empty
  Eigen::Matrix4d T_zero_ = Eigen::Matrix4d::Identity();  // T_meas_tool(0)
  Eigen::Matrix<double, 6, Eigen::Dynamic> screws_;       // (v, omega) of each joint at q = 0
  Eigen::VectorXd offset_;
  TableInfo info_;
};

}  // namespace kincal
