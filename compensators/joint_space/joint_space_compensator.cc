#include "compensators/joint_space/joint_space_compensator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Cholesky>

#include "compensators/common/random_targets.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal {
namespace {

using Pose34 = PoseExpansion::Pose34;

}  // namespace

JointSpaceCompensator::JointSpaceCompensator() : JointSpaceCompensator(Options()) {}

bool JointSpaceCompensator::Options::IsValid(std::string* why) const {
  const auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (degree < 1 || degree > 8) return fail("degree must be 1 to 8");
  if (steps < 1 || steps > 5) return fail("steps must be 1 to 5");
  if (!(length_scale > 0)) return fail("length_scale must be > 0");
  if (!(damping >= 0)) return fail("damping must be >= 0");
  if (!(max_step > 0)) return fail("max_step must be > 0");
  if (!(position_tolerance > 0) || !(orientation_tolerance > 0)) return fail("tolerances must be > 0");
  if (!(max_fit_error > 0)) return fail("max_fit_error must be > 0");
  if (!(max_table_bytes > 0)) return fail("max_table_bytes must be > 0");
  return true;
}

JointSpaceCompensator::Options JointSpaceCompensator::Options::FromYaml(const YAML::Node& node) {
  Options o;
  OptionsReader reader(node, "joint_space");
  reader.Get("degree", &o.degree);
  reader.Get("steps", &o.steps);
  reader.GetLength("length_scale", &o.length_scale);
  reader.Get("damping", &o.damping);
  reader.Get("max_step", &o.max_step);
  reader.GetLength("position_tolerance", &o.position_tolerance);
  reader.Get("orientation_tolerance", &o.orientation_tolerance);
  reader.Get("max_fit_error", &o.max_fit_error);
  reader.Get("max_table_bytes", &o.max_table_bytes);
  reader.Finish();
  return o;
}

void JointSpaceCompensator::DoPrepare() {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("joint_space: " + why);
  const Robot& id = identified();
  const KinematicModel& model = id.model();
  const int n = id.dof();
  if (n < 2 || n > kMaxJoints) throw std::invalid_argument("joint_space: needs 2 to 16 joints");
  const double bytes = 12 * sizeof(double) * (2.0 * options_.degree + 1) * n;
  if (bytes > options_.max_table_bytes) throw std::invalid_argument("joint_space: the expansion exceeds max_table_bytes");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::Isometry3d T0 = model.ForwardKinematics(zero), T0_inv = T0.inverse();
  T_zero_ = T0.matrix();
  factors_.clear();
  for (int j = 0; j < n; ++j) {
    const auto [low, high] = id.Limit(j);
    factors_.push_back(PoseExpansion::Fit({{j, model.joint_type(j), low, high}}, options_.degree, zero,
                                          [&](const Eigen::VectorXd& q) {
                                            return Eigen::Isometry3d(model.ForwardKinematics(q) * T0_inv);
                                          }));
  }

  // Screws at q = 0: dX_j/dq_j at 0 is [omega_j]x | v_j, X_j(0) being the identity.
  screws_.resize(6, n);
  for (int j = 0; j < n; ++j) {
    Pose34 X, dX;
    factors_[j].EvaluateSingle(0.0, &X, &dX);
    screws_.col(j).head<3>() = dX.col(3);
    screws_.col(j).tail<3>() = 0.5 * Eigen::Vector3d(dX(2, 1) - dX(1, 2), dX(0, 2) - dX(2, 0), dX(1, 0) - dX(0, 1));
  }

  // The fit against the model at random configurations (every angle for revolute joints: the series
  // is periodic; prismatic joints within their limits).
  info_ = TableInfo();
  Rng rng(20261123);
  for (int i = 0; i < 200; ++i) {
    Joints q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = id.Limit(j);
      q[j] = model.joint_type(j) == JointType::kRevolute ? rng.Uniform(-M_PI, M_PI) : rng.Uniform(low, high);
    }
    Eigen::Isometry3d T;
    Pose(q, &T);
    const Eigen::Isometry3d T_model = model.ForwardKinematics(q);
    info_.fit_position_error = std::max(info_.fit_position_error, (T.translation() - T_model.translation()).norm());
    info_.fit_orientation_error =
        std::max(info_.fit_orientation_error, (T.linear() - T_model.linear()).cwiseAbs().maxCoeff());
  }
  if (!(info_.fit_position_error <= options_.max_fit_error && info_.fit_orientation_error <= options_.max_fit_error)) {
    throw std::invalid_argument("joint_space: the degree-" + std::to_string(options_.degree) + " expansion misses the " +
                                "identified model by " + std::to_string(info_.fit_position_error) + " m, " +
                                std::to_string(info_.fit_orientation_error) + " (over max_fit_error)");
  }
  // The common part of the correction (header): exact corrections at well-conditioned random
  // configurations of the nominal robot, solved offline by as many steps as they need.
  offset_ = Eigen::VectorXd::Zero(n);
  std::vector<std::vector<double>> corrections(n);
  for (int attempt = 0; attempt < 1000 && corrections[0].size() < 100; ++attempt) {
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = nominal().Limit(j);
      q[j] = rng.Uniform(low, high);
    }
    if (JacobianConditionRatio(nominal().model(), q, options_.length_scale) < 0.02) continue;
    CompensationTarget target;
    target.T_meas_tool = nominal().model().ForwardKinematics(q);
    Joints q_id = q;
    bool cut = false;
    Steps(target, 20, &q_id, &cut);
    Eigen::Isometry3d T;
    Pose(q_id, &T);
    if (PoseError(T, target.T_meas_tool).norm() > 1e-9) continue;
    for (int j = 0; j < n; ++j) corrections[j].push_back(q_id[j] - q[j]);
  }
  for (int j = 0; j < n && !corrections[j].empty(); ++j) {
    std::vector<double>& c = corrections[j];
    std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
    offset_[j] = c[c.size() / 2];
  }
  info_.offset_samples = static_cast<int>(corrections[0].size());
  info_.factors = n;
  info_.terms = factors_[0].num_terms();
  info_.memory_bytes = sizeof(T_zero_) + offset_.size() * sizeof(double);
  for (const PoseExpansion& f : factors_) info_.memory_bytes += f.memory_bytes();
  info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool JointSpaceCompensator::Pose(const Joints& q, Eigen::Isometry3d* T_meas_tool, Jacobian* J) const {
  const int n = static_cast<int>(q.size());
  // P = X_1 .. X_j as rotation and translation; the spatial twist of joint j is its screw at q = 0
  // carried by X_1 .. X_(j-1) (Murray, Li and Sastry eq. 3.54): omega = R_P omega_j,
  // v = R_P v_j + p_P x omega, v being the velocity of the point at the frame's origin.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  bool inside = true;
  Eigen::Matrix<double, 6, kMaxJoints> twist;
  for (int j = 0; j < n; ++j) {
    if (J) {
      twist.col(j).tail<3>() = R * screws_.col(j).tail<3>();
      twist.col(j).head<3>() = R * screws_.col(j).head<3>() + p.cross(twist.col(j).tail<3>());
    }
    Pose34 X;
    inside = factors_[j].EvaluateSingle(q[j], &X) && inside;
    p += R * X.col(3);
    R = R * X.leftCols<3>();
  }
  T_meas_tool->linear() = R * T_zero_.topLeftCorner<3, 3>();
  T_meas_tool->translation() = R * T_zero_.topRightCorner<3, 1>() + p;
  if (!J) return inside;
  J->resize(6, n);
  const Eigen::Vector3d p_tool = T_meas_tool->translation();
  for (int j = 0; j < n; ++j) {
    J->col(j).tail<3>() = twist.col(j).tail<3>();
    J->col(j).head<3>() = twist.col(j).head<3>() + twist.col(j).tail<3>().cross(p_tool);
  }
  return inside;
}

bool JointSpaceCompensator::Steps(const CompensationTarget& target, int steps, Joints* q, bool* cut) const {
  const int n = static_cast<int>(q->size());
  const int rows = target.has_orientation ? 6 : 3;
  Vector6d weights = Vector6d::Ones();
  weights.head<3>() /= options_.length_scale;
  const double mu = options_.damping * options_.damping;
  Jacobian J;
  Eigen::Isometry3d T;
  bool inside = true;
  for (int step = 0; step < steps; ++step) {
    inside = Pose(*q, &T, &J) && inside;
    const Vector6d e = weights.cwiseProduct(PoseError(T, target.T_meas_tool));
    const Jacobian A = weights.asDiagonal() * J;
    Joints dq(n);
    if (n == 6 && rows == 6) {
      Eigen::Matrix<double, 6, 6> normal;
      const Eigen::Matrix<double, 6, 6> A6 = A;
      normal.noalias() = A6.transpose() * A6;
      normal.diagonal().array() += mu;
      dq = normal.llt().solve(A6.transpose() * e);
    } else {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints> normal(n, n);
      normal.noalias() = A.topRows(rows).transpose() * A.topRows(rows);
      normal.diagonal().array() += mu;
      // LDLT: with damping 0 a position-only target leaves the normal matrix singular.
      dq = normal.ldlt().solve(A.topRows(rows).transpose() * e.head(rows));
    }
    const double length = dq.norm();
    if (!(length <= options_.max_step)) {
      dq *= std::isfinite(length) ? options_.max_step / length : 0.0;
      *cut = true;
    }
    *q += dq;
  }
  return inside;
}

void JointSpaceCompensator::DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                                         CompensationResult* result) const {
  Joints q = seed + offset_;
  bool cut = false;
  bool inside = Steps(target, options_.steps, &q, &cut);
  Eigen::Isometry3d T;
  inside = Pose(q, &T) && inside;
  const Vector6d e = PoseError(T, target.T_meas_tool);
  const double position = e.head<3>().norm(), orientation = target.has_orientation ? e.tail<3>().norm() : 0.0;
  result->q_actual = q;
  result->report.iterations = options_.steps;
  if (!inside) {
    result->report.status = CompensationStatus::kFailed;
    result->report.message = "a prismatic joint left the range the expansion was fitted over";
  } else if (position <= options_.position_tolerance && orientation <= options_.orientation_tolerance) {
    result->report.status = CompensationStatus::kConverged;
  } else if (cut) {
    result->report.status = CompensationStatus::kSingular;
    result->report.message = "a step was cut to max_step (near a singular configuration)";
  } else {
    result->report.status = CompensationStatus::kIterationLimit;
    result->report.message = "the fixed Jacobian steps left the pose off the target (see the errors)";
  }
}

}  // namespace kincal
