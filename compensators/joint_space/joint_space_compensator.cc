#include "compensators/joint_space/joint_space_compensator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Cholesky>

#include "compensators/common/random_targets.h"
#include "framework/error.h"
#include "framework/math.h"
#include "framework/median.h"
#include "framework/random.h"

namespace kincal {
namespace {

using Pose34 = PoseExpansion::Pose34;

}  // namespace

JointSpaceCompensator::JointSpaceCompensator() : JointSpaceCompensator(Options()) {}

const OptionTable<JointSpaceCompensator::Options>& JointSpaceCompensator::Options::Table() {
  using O = Options;
  static const OptionTable<O> table =
      OptionTable<O>("joint_space")
          .Add("degree", &O::degree, "degree of the series in each joint", Within(1, 8))
          .Add("steps", &O::steps, "Jacobian steps at run time", Within(1, 5))
          .Add("length_scale", OptionUnit::kLength, &O::length_scale, "position rows are divided by it", Positive())
          .Add("damping", &O::damping, "Levenberg damping (its square is mu)", NonNegative())
          .Add("max_step", &O::max_step, "rad: the longest step", Positive())
          .Add("singular_ratio", &O::singular_ratio,
               "off target with sigma_min / sigma_max below this at the result: singular", NonNegative())
          .Add("position_tolerance", OptionUnit::kLength, &O::position_tolerance, "converged within this position",
               Positive())
          .Add("orientation_tolerance", &O::orientation_tolerance, "rad: ... and this orientation", Positive())
          .Add("max_fit_error", &O::max_fit_error, "Prepare() fails when the expansion misses by more", Positive())
          .Add("max_table_bytes", &O::max_table_bytes, "refuse larger expansions", Positive());
  return table;
}

bool JointSpaceCompensator::Options::IsValid(std::string* why) const { return Table().Validate(*this, why); }

JointSpaceCompensator::Options JointSpaceCompensator::Options::FromYaml(const YAML::Node& node) {
  return Table().Read(node);
}

void JointSpaceCompensator::DoPrepare() {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("joint_space: " + OneLine(why));
  const Robot& id = identified();
  const KinematicModel& model = id.model();
  const int n = id.dof();
  if (n < 2 || n > kMaxJoints) throw std::invalid_argument("joint_space: needs 2 to 16 joints");
  const double bytes = 12 * sizeof(double) * (2.0 * options_.degree + 1) * n;
  if (bytes > options_.max_table_bytes)
    throw std::invalid_argument("joint_space: the expansion exceeds max_table_bytes");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::Isometry3d T0 = model.ForwardKinematics(zero), T0_inv = T0.inverse();
  T_zero_ = T0.matrix();
  factors_.clear();
  for (int j = 0; j < n; ++j) {
    const auto [low, high] = id.Limit(j);
    factors_.push_back(PoseExpansion::Fit(
        {{j, model.joint_type(j), low, high}}, options_.degree, zero,
        [&](const Eigen::VectorXd& q) { return Eigen::Isometry3d(model.ForwardKinematics(q) * T0_inv); }));
  }

  revolute_.clear();
  bool all_revolute = options_.degree == 1;
  for (int j = 0; j < n; ++j) all_revolute = all_revolute && model.joint_type(j) == JointType::kRevolute;
  for (int j = 0; all_revolute && j < n; ++j) {
    revolute_.push_back({factors_[j].Term(0), factors_[j].Term(1), factors_[j].Term(2)});
  }

  // Screws at q = 0: dX_j/dq_j at 0 is [omega_j]x | v_j, X_j(0) being the identity.
  screws_.resize(6, n);
  for (int j = 0; j < n; ++j) {
    Pose34 X, dX;
    factors_[j].EvaluateSingle(0.0, &X, &dX);
    screws_.col(j).head<3>() = dX.col(3);
    screws_.col(j).tail<3>() = 0.5 * Eigen::Vector3d(dX(2, 1) - dX(1, 2), dX(0, 2) - dX(2, 0), dX(1, 0) - dX(0, 1));
  }

  info_ = TableInfo();
  Rng rng(20261123);
  MeasureFit(&rng);
  FitOffset(&rng);
  info_.factors = n;
  info_.terms = factors_[0].num_terms();
  info_.memory_bytes = sizeof(T_zero_) + offset_.size() * sizeof(double);
  for (const PoseExpansion& f : factors_) info_.memory_bytes += f.memory_bytes();
  info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void JointSpaceCompensator::MeasureFit(Rng* rng) {
  const Robot& id = identified();
  const KinematicModel& model = id.model();
  const int n = id.dof();
  // The fit against the model at random configurations (every angle for revolute joints: the series
  // is periodic; prismatic joints within their limits).
  for (int i = 0; i < 200; ++i) {
    Joints q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = id.Limit(j);
      q[j] = model.joint_type(j) == JointType::kRevolute ? rng->Uniform(-M_PI, M_PI) : rng->Uniform(low, high);
    }
    Eigen::Isometry3d T;
    Pose(q, &T);
    const Eigen::Isometry3d T_model = model.ForwardKinematics(q);
    info_.fit_position_error = std::max(info_.fit_position_error, (T.translation() - T_model.translation()).norm());
    info_.fit_orientation_error =
        std::max(info_.fit_orientation_error, (T.linear() - T_model.linear()).cwiseAbs().maxCoeff());
  }
  if (!(info_.fit_position_error <= options_.max_fit_error && info_.fit_orientation_error <= options_.max_fit_error)) {
    throw std::invalid_argument("joint_space: the degree-" + std::to_string(options_.degree) +
                                " expansion misses the " + "identified model by " +
                                std::to_string(info_.fit_position_error) + " m, " +
                                std::to_string(info_.fit_orientation_error) + " (over max_fit_error)");
  }
}

void JointSpaceCompensator::FitOffset(Rng* rng) {
  const int n = identified().dof();
  // The common part of the correction (header): exact corrections at well-conditioned random
  // configurations of the nominal robot, solved offline by as many steps as they need.
  offset_ = Eigen::VectorXd::Zero(n);
  std::vector<std::vector<double>> corrections(n);
  for (int attempt = 0; attempt < 1000 && corrections[0].size() < 100; ++attempt) {
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = nominal().Limit(j);
      q[j] = rng->Uniform(low, high);
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
  for (int j = 0; j < n && !corrections[j].empty(); ++j) offset_[j] = Median(corrections[j]);
  info_.offset_samples = static_cast<int>(corrections[0].size());
}

void JointSpaceCompensator::JointTrig::Set(const Joints& q) {
  for (int j = 0; j < q.size(); ++j) {
    c[j] = std::cos(q[j]);
    s[j] = std::sin(q[j]);
  }
}

void JointSpaceCompensator::JointTrig::Advance(const Joints& dq) {
  for (int j = 0; j < dq.size(); ++j) {
    const double x = dq[j];
    double cd, sd;
    if (std::abs(x) <= 0.6) {
      // Taylor series to x^13 / x^12: the remainder is below 0.6^14 / 14! ~ 9e-15 relative to 1... and
      // each step's own error is what the next step corrects.
      const double x2 = x * x;
      sd = x * (1 + x2 * (-1.0 / 6 +
                          x2 * (1.0 / 120 + x2 * (-1.0 / 5040 +
                                                  x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800 + x2 / 6227020800.0))))));
      cd = 1 + x2 * (-0.5 + x2 * (1.0 / 24 +
                                  x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800 + x2 / 479001600.0)))));
    } else {
      cd = std::cos(x);
      sd = std::sin(x);
    }
    const double c0 = c[j], s0 = s[j];
    c[j] = c0 * cd - s0 * sd;
    s[j] = s0 * cd + c0 * sd;
  }
}

namespace {

// T_meas_tool = X_1 .. X_n T(0), and (J not null) its Jacobian, with `factor(j, &X)` giving X_j (false when
// outside its fitted range). The spatial twist of joint j is its screw at q = 0 carried by X_1 .. X_(j-1)
// (Murray, Li and Sastry eq. 3.54): omega = R omega_j, v = R v_j + p x omega for the point at the
// origin, moved to the tool point at the end. JacobianOut: the dynamic Jacobian or a fixed 6 x 6.
template <typename FactorFn, typename JacobianOut>
bool PoseProduct(int n, const FactorFn& factor, const Eigen::Matrix<double, 6, Eigen::Dynamic>& screws,
                 const Eigen::Matrix4d& T_zero, Eigen::Isometry3d* T_meas_tool, JacobianOut* J) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  bool inside = true;
  if (J && J->cols() != n) J->resize(6, n);
  for (int j = 0; j < n; ++j) {
    if (J) {
      const Eigen::Vector3d w = R * screws.col(j).tail<3>();
      J->col(j).template tail<3>() = w;
      J->col(j).template head<3>().noalias() = R * screws.col(j).head<3>() + p.cross(w);
    }
    Pose34 X;
    inside = factor(j, &X) && inside;
    p.noalias() += R * X.col(3);
    R = R * X.leftCols<3>();
  }
  T_meas_tool->linear() = R * T_zero.topLeftCorner<3, 3>();
  T_meas_tool->translation() = R * T_zero.topRightCorner<3, 1>() + p;
  if (!J) return inside;
  const Eigen::Vector3d p_tool = T_meas_tool->translation();
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d w = J->col(j).template tail<3>();
    J->col(j).template head<3>() += w.cross(p_tool);
  }
  return inside;
}

// Solves N x = b for the symmetric 6 x 6 N whose lower triangle is given, by Cholesky with the loops'
// bounds fixed: a quarter of a lookup went to Eigen's LLT, which runs its general (dynamic-size) kernels
// even for a fixed 6 x 6. A pivot that is not positive (N singular without damping) gives NaN, which the
// caller's step-length check turns into a cut step.
Vector6d SolveSymmetric6(Eigen::Matrix<double, 6, 6> N, Vector6d b) {
  double inv_diag[6];  // multiplications instead of divisions in the substitutions
  for (int c = 0; c < 6; ++c) {
    double d = N(c, c);
    for (int k = 0; k < c; ++k) d -= N(c, k) * N(c, k);
    inv_diag[c] = d > 0.0 ? 1.0 / std::sqrt(d) : NAN;
    for (int r = c + 1; r < 6; ++r) {
      double v = N(r, c);
      for (int k = 0; k < c; ++k) v -= N(r, k) * N(c, k);
      N(r, c) = v * inv_diag[c];
    }
  }
  for (int r = 0; r < 6; ++r) {  // L y = b
    for (int k = 0; k < r; ++k) b[r] -= N(r, k) * b[k];
    b[r] *= inv_diag[r];
  }
  for (int r = 5; r >= 0; --r) {  // L^T x = y
    for (int k = r + 1; k < 6; ++k) b[r] -= N(k, r) * b[k];
    b[r] *= inv_diag[r];
  }
  return b;
}

}  // namespace

bool JointSpaceCompensator::Pose(const Joints& q, Eigen::Isometry3d* T_meas_tool, Jacobian* J) const {
  if (!revolute_.empty()) {
    JointTrig trig;
    trig.Set(q);
    return Pose(q, trig, T_meas_tool, J);
  }
  const auto factor = [&](int j, Pose34* X) { return factors_[j].EvaluateSingle(q[j], X); };
  return PoseProduct(static_cast<int>(q.size()), factor, screws_, T_zero_, T_meas_tool, J);
}

bool JointSpaceCompensator::Pose(const Joints& q, const JointTrig& trig, Eigen::Isometry3d* T_meas_tool,
                                 Jacobian* J) const {
  const auto factor = [&](int j, Pose34* X) {
    const RevoluteFactor& f = revolute_[j];
    X->noalias() = f.c0 + trig.c[j] * f.c1 + trig.s[j] * f.c2;
    return true;
  };
  return PoseProduct(static_cast<int>(q.size()), factor, screws_, T_zero_, T_meas_tool, J);
}

void JointSpaceCompensator::PoseJacobian6(const JointTrig& trig, Eigen::Isometry3d* T_meas_tool,
                                          Eigen::Matrix<double, 6, 6>* J) const {
  const auto factor = [&](int j, Pose34* X) {
    const RevoluteFactor& f = revolute_[j];
    X->noalias() = f.c0 + trig.c[j] * f.c1 + trig.s[j] * f.c2;
    return true;
  };
  PoseProduct(6, factor, screws_, T_zero_, T_meas_tool, J);
}

bool JointSpaceCompensator::Steps(const CompensationTarget& target, int steps, Joints* q, bool* cut) const {
  const int n = static_cast<int>(q->size());
  const int rows = target.has_orientation ? 6 : 3;
  Vector6d weights = Vector6d::Ones();
  weights.head<3>() /= options_.length_scale;
  const double mu = options_.damping * options_.damping;
  const bool fast = !revolute_.empty();
  Jacobian J;
  Eigen::Isometry3d T;
  bool inside = true;
  JointTrig trig;
  if (fast) trig.Set(*q);
  for (int step = 0; step < steps; ++step) {
    Eigen::Matrix<double, 6, 6> A;
    const bool fixed6 = n == 6 && rows == 6;
    if (fast && fixed6) {
      PoseJacobian6(trig, &T, &A);
    } else if (fast) {
      Pose(*q, trig, &T, &J);
    } else {
      inside = Pose(*q, &T, &J) && inside;
    }
    const Vector6d e = weights.cwiseProduct(PoseError(T, target.T_meas_tool));
    Joints dq(n);
    if (fixed6) {
      // Fixed sizes: the common 6-joint pose target.
      if (!fast) A = J.leftCols<6>();
      A.topRows<3>() *= weights[0];
      // The lower triangle of A^T A + mu I only: what the Cholesky factorisation reads.
      Eigen::Matrix<double, 6, 6> normal;
      for (int c = 0; c < 6; ++c) {
        for (int r = c; r < 6; ++r) normal(r, c) = A.col(r).dot(A.col(c));
        normal(c, c) += mu;
      }
      dq = SolveSymmetric6(normal, A.transpose() * e);
    } else {
      const Jacobian A = weights.asDiagonal() * J;
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
    if (fast) trig.Advance(dq);
  }
  return inside;
}

void JointSpaceCompensator::DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                                         CompensationResult* result) const {
  Joints q = seed + offset_;
  bool cut = false;
  const bool inside = Steps(target, options_.steps, &q, &cut) && InsideFittedRanges(q);
  result->q_actual = q;
  result->report.iterations = options_.steps;
  // Provisional: JudgeErrors() decides from the model's errors at q, which Compensate() computes.
  if (!inside) {
    result->report.status = CompensationStatus::kFailed;
    result->report.message = "a prismatic joint left the range the expansion was fitted over";
  } else if (cut) {
    result->report.status = CompensationStatus::kSingular;
    result->report.message = "a step was cut to max_step (near a singular configuration)";
  } else {
    result->report.status = CompensationStatus::kConverged;
  }
}

void JointSpaceCompensator::JudgeErrors(const CompensationTarget& target, CompensationResult* result) const {
  CompensationReport& r = result->report;
  if (r.status != CompensationStatus::kConverged && r.status != CompensationStatus::kSingular) return;
  if (r.position_error <= options_.position_tolerance && r.orientation_error <= options_.orientation_tolerance) {
    r.status = CompensationStatus::kConverged;
    r.message.clear();
  } else if (r.status == CompensationStatus::kConverged) {
    if (options_.singular_ratio > 0.0 && NearSingular(target, result->q_actual)) {
      r.status = CompensationStatus::kSingular;
      r.message = "the fixed Jacobian steps stopped off the target near a singular configuration";
    } else {
      r.status = CompensationStatus::kIterationLimit;
      r.message = "the fixed Jacobian steps left the pose off the target (see the errors)";
    }
  }
}

bool JointSpaceCompensator::NearSingular(const CompensationTarget& target, const Eigen::VectorXd& q) const {
  Jacobian J;
  Eigen::Isometry3d T;
  Pose(Joints(q), &T, &J);
  J.topRows<3>() /= options_.length_scale;
  const int rows = target.has_orientation ? 6 : 3;
  // The nonzero singular values of the rows used are the square roots of the eigenvalues of the smaller
  // Gram matrix G (at most 6 x 6).
  using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
  const Gram G = rows <= J.cols() ? Gram(J.topRows(rows) * J.topRows(rows).transpose())
                                  : Gram(J.topRows(rows).transpose() * J.topRows(rows));
  const double ratio2 = options_.singular_ratio * options_.singular_ratio;
  // lambda_max <= trace(G) and 1 / lambda_min <= trace(G^-1) = |L^-1|_F^2: when that lower bound of
  // lambda_min / lambda_max clears the threshold (nearly always away from singular configurations), the
  // singular values are not needed.
  const Eigen::LLT<Gram> llt(G);
  if (llt.info() == Eigen::Success) {
    const Gram L_inv = llt.matrixL().solve(Gram::Identity(G.rows(), G.cols()));
    if (1.0 / (G.trace() * L_inv.squaredNorm()) >= ratio2) return false;
  }
  // Near the threshold: the singular values themselves (rare, so the shared SVD of compensators/common
  // rather than an eigen solver of this Gram type, which doubled this file's compile time).
  return !(SingularValueRatio(J.topRows(rows)) >= options_.singular_ratio);
}

bool JointSpaceCompensator::InsideFittedRanges(const Joints& q) const {
  for (const PoseExpansion& f : factors_) {
    const PoseExpansion::Axis& axis = f.axes()[0];
    if (axis.type == JointType::kPrismatic && !(q[axis.joint] >= axis.low && q[axis.joint] <= axis.high)) return false;
  }
  return true;
}

}  // namespace kincal
