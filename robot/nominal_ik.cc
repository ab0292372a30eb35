// NominalInverseKinematics::Impl: detection of the closed form, branch solvers, polishing and choice of
// branch, which share its private state; the geometric subproblems it calls live in ik_geometry.cc, the
// options' table in ik_options.cc.
#include "robot/nominal_ik.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "framework/damped_least_squares.h"
#include "framework/error.h"
#include "robot/ik_geometry.h"
#include "framework/math.h"
#include "framework/random.h"
#include "framework/svd.h"
#include "models/chain_model.h"

namespace kincal {

std::string ToString(IkStatus status) {
  switch (status) {
    case IkStatus::kSolved:
      return "solved";
    case IkStatus::kOutOfLimits:
      return "out_of_limits";
    case IkStatus::kUnreachable:
      return "unreachable";
    case IkStatus::kSingular:
      return "singular";
  }
  return "unknown";
}

namespace {

using namespace ik;  // robot/ik_geometry.h
using Eigen::VectorXd;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// |A^-1|_F by Gauss-Jordan elimination with partial pivoting, NaN where a pivot is 0. Eigen's LU inverse
// runs its blocked triangular solvers even at a fixed 6 x 6, at several times the cost.
double InverseNorm(Matrix6d A) {
  Matrix6d B = Matrix6d::Identity();
  for (int k = 0; k < 6; ++k) {
    int p = 0;
    A.col(k).tail(6 - k).cwiseAbs().maxCoeff(&p);
    p += k;
    if (A(p, k) == 0.0) return NAN;
    A.row(k).swap(A.row(p));
    B.row(k).swap(B.row(p));
    // Columns of A up to k are settled (zero outside the pivots, never read again): only those right
    // of the pivot are carried along.
    const int right = 5 - k;
    const double inverse = 1.0 / A(k, k);
    A.row(k).tail(right) *= inverse;
    B.row(k) *= inverse;
    for (int i = 0; i < 6; ++i) {
      if (i == k) continue;
      const double f = A(i, k);
      A.row(i).tail(right) -= f * A.row(k).tail(right);
      B.row(i) -= f * B.row(k);
    }
  }
  return B.norm();
}

}  // namespace

// Closed-form branches of a 6-joint arm: at most 16 positions of the 3R chain (8 roots, two angles
// where its equations are dependent) times 3 for the rest (2, and a free pair next to a singularity).
using BranchList = FixedList<Vector6d, 48>;

struct NominalInverseKinematics::Impl {
  enum class Kind { kNumeric, kPieper, kParallel };
  Robot robot;
  NominalIkOptions options;
  int n = 0;
  Kind kind = Kind::kNumeric;
  int first = 0;                           // first joint (0-based, in the solved chain) of the triple
  bool reversed = false;                   // the chain is solved backwards (T^-1, joints in reverse order)
  std::vector<Screw> screws;               // of the solved chain
  Isometry3d T0 = Isometry3d::Identity();  // of the solved chain
  Vector3d center = Vector3d::Zero();      // Pieper: where the triple meets; parallel: where the pair meets
  VectorXd middle;

  void Detect();
  // Raw closed-form branches (unpolished, unwrapped) in the model's joint order. Where a family of
  // solutions is continuous (a singular pose: two axes in line, a point on an axis), its free joint takes
  // its value from `free` (model order) and sets its bit (1 << joint) in *free_mask.
  BranchList Branches(const Isometry3d& T, const VectorXd& free, int* free_mask) const;
  // The same for the solved chain (reversed or not), `free` in its order, bits of its joints.
  void PieperBranches(const Isometry3d& M, const Vector6d& free, BranchList* out, int* free_mask) const;
  void ParallelBranches(const Isometry3d& M, const Vector6d& free, BranchList* out, int* free_mask) const;
  // The solution a controller takes among `branches` (ranked: inside the limits, the named
  // configuration, the distance to the reference), polished; false when none reaches the pose.
  // *unfinished: the polished joints of the first candidate inside the limits that did not reach it
  // (next to a singular configuration, where the closed form loses accuracy), else empty.
  bool Choose(const Isometry3d& T, const VectorXd& reference, BranchList* branches, IkSolution* s,
              VectorXd* unfinished = nullptr) const;
  // A pose whose solution family is continuous (free joints in free_mask) and whose member at the
  // reference leaves the limits: the member inside the limits whose free joint is closest to the
  // reference's (one free joint moved at a time); false when no member is inside.
  bool SearchFamily(const Isometry3d& T, const VectorXd& reference, int free_mask, IkSolution* s) const;
  // Newton on the model; returns the errors.
  // *jacobian (optional): the joint Jacobian at the returned joints, which the pass computes anyway.
  void Polish(const Isometry3d& T, VectorXd* q, double* pe, double* oe, Matrix6Xd* jacobian = nullptr) const;
  // Whole turns into the limits, nearest the reference (robot/robot.h); a joint within 1e-9 outside
  // its limit (a solution on the limit, with the rounding of the closed form or the polish) is clamped
  // onto it, *clamped set.
  bool WrapIntoLimits(const VectorXd& reference, Eigen::Ref<VectorXd> q, bool* clamped = nullptr) const {
    return kincal::WrapIntoLimits(robot, &reference, q, 1e-9, clamped);
  }
  // jacobian: the joint Jacobian at q if known.
  bool Singular(const VectorXd& q, const Matrix6Xd* jacobian = nullptr) const;
  bool MatchesConfiguration(const Eigen::Ref<const VectorXd>& q) const;
  // The numeric solver from `start` (the reference when empty), with `restarts` (< 0: the options').
  IkSolution Numeric(const Isometry3d& T, bool orientation, const VectorXd& reference, const VectorXd& start = {},
                     int restarts = -1) const;
};

void NominalInverseKinematics::Impl::Detect() {
  const KinematicModel& model = robot.model();
  if (n != 6 || !options.use_closed_form) return;
  for (int j = 0; j < n; ++j) {
    if (model.joint_type(j) != JointType::kRevolute) return;
  }
  const VectorXd zero = VectorXd::Zero(n);
  const Isometry3d T_zero = model.ForwardKinematics(zero);
  const Matrix6Xd J = model.JointJacobian(zero);
  std::vector<Screw> forward(n);
  double length = 1.0;
  for (int j = 0; j < n; ++j) {
    const Vector3d w = J.col(j).tail<3>(), v = J.col(j).head<3>();
    if (std::abs(w.norm() - 1) > 1e-9) return;
    forward[j] = {w, T_zero.translation() + w.cross(v)};
    length = std::max(length, forward[j].p.norm());
  }
  // The product of exponentials must be the model (it is for every serial chain of revolute joints).
  Rng rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    VectorXd q(n);
    for (int j = 0; j < n; ++j) q[j] = rng.Uniform(-M_PI, M_PI);
    Isometry3d T = Isometry3d::Identity();
    for (int j = 0; j < n; ++j) T = T * Exp(forward[j], q[j]);
    T = T * T_zero;
    const Vector6d e = PoseError(T, model.ForwardKinematics(q));
    if (!(e.head<3>().norm() < 1e-9 * length && e.tail<3>().norm() < 1e-9)) return;
  }
  // The reversed chain: T^-1 = E'_n(q_n) ... E'_1(q_1) T0^-1 with E'_j = E of -(T0^-1 s_j).
  std::vector<Screw> backward(n);
  const Isometry3d T_inv = T_zero.inverse();
  for (int j = 0; j < n; ++j) backward[n - 1 - j] = {-(T_inv.linear() * forward[j].w), T_inv * forward[j].p};
  const double dtol = options.distance_tolerance, wtol = options.direction_tolerance;
  const auto parallel = [&](const Screw& a, const Screw& b) { return a.w.cross(b.w).norm() < wtol; };
  // Pieper: prefer the wrist (the last three), then the others.
  for (int t : {3, 0, 1, 2}) {
    if (parallel(forward[t], forward[t + 1]) || parallel(forward[t + 1], forward[t + 2])) continue;
    double distance = 0.0;
    const Vector3d w = CommonPoint(&forward[t], 3, &distance);
    if (distance < dtol * length) {
      kind = Kind::kPieper;
      first = t;
      screws = forward;
      T0 = T_zero;
      center = w;
      return;
    }
  }
  // Three parallel axes 2, 3, 4 with axes 5 and 6 meeting (or the mirror image, by reversal).
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<Screw>& s = pass == 0 ? forward : backward;
    if (!parallel(s[1], s[2]) || !parallel(s[2], s[3]) || parallel(s[0], s[1]) || parallel(s[4], s[5])) continue;
    if (LineDistance(s[1], s[2]) < dtol * length || LineDistance(s[2], s[3]) < dtol * length) continue;
    if (LineDistance(s[4], s[5]) > dtol * length) continue;
    double distance = 0.0;
    const Vector3d u = CommonPoint(&s[4], 2, &distance);
    kind = Kind::kParallel;
    first = 1;
    reversed = pass == 1;
    screws = s;
    T0 = pass == 0 ? T_zero : T_inv;
    center = u;
    return;
  }
}

void NominalInverseKinematics::Impl::PieperBranches(const Isometry3d& M, const Vector6d& free, BranchList* out,
                                                    int* free_mask) const {
  // Joints after the triple, moved by M, then those before: the 3R chain that takes w to M w.
  int outer[3];
  Screw chain[3];
  int k = 0;
  for (int j = first + 3; j < n; ++j, ++k) {
    outer[k] = j;
    chain[k] = Moved(M, screws[j]);
  }
  for (int j = 0; j < first; ++j, ++k) {
    outer[k] = j;
    chain[k] = screws[j];
  }
  const double free_outer[3] = {free[outer[0]], free[outer[1]], free[outer[2]]};
  int mask = 0;
  FixedList<Matrix3d, 16> rotations;
  const Positions positions =
      Solve3R(chain[0], chain[1], chain[2], center, M * center, free_outer, &mask, &rotations);
  for (int i = 0; i < 3; ++i) {
    if (mask & (1 << i)) *free_mask |= 1 << outer[i];
  }
  const Vector3d& w1 = screws[first].w;
  const Vector3d& w2 = screws[first + 1].w;
  const Vector3d& w3 = screws[first + 2].w;
  const Vector3d e = Across(w3);
  for (int position = 0; position < positions.size; ++position) {
    Vector6d q = Vector6d::Zero();
    for (int i = 0; i < 3; ++i) q[outer[i]] = positions.item[position][i];
    // The triple's rotation R_before^T R_M R_after^T is the chain's P^T R_M: its joints after the triple
    // turn about axes moved by M, P = R_M R_after R_M^T R_before.
    const Matrix3d R_N = rotations.item[position].transpose() * M.linear();
    int wrist = 0;
    const AnglePairs pairs = Subproblem2(w1, w2, w3, R_N * w3, free[first], free[first + 1], &wrist);
    const Vector3d R_N_e = R_N * e;
    for (int pair = 0; pair < pairs.size; ++pair) {
      const CosSin(&cs)[2] = pairs.cs[pair];
      q[first] = pairs.pair[pair].first;
      q[first + 1] = pairs.pair[pair].second;
      // (R_1 R_2)^T R_N e, one vector at a time.
      q[first + 2] = Subproblem1(w3, e, Rot(w2, cs[1]).transpose() * (Rot(w1, cs[0]).transpose() * R_N_e));
      out->Push(q);
    }
    *free_mask |= wrist << first;
  }
}

void NominalInverseKinematics::Impl::ParallelBranches(const Isometry3d& M, const Vector6d& free, BranchList* out,
                                                      int* free_mask) const {
  const Screw &X = screws[0], &P1 = screws[1], &P2 = screws[2], &P3 = screws[3], &Y = screws[4], &Z = screws[5];
  const PlanarElbow elbow(P1, P2, P3);
  const Vector3d &w = elbow.w, &c1 = elbow.c1, &c2 = elbow.c2, &dv = elbow.dv;
  const double dist = elbow.dist, r2 = elbow.r2;
  if (dist < 1e-12) return;  // P1 and P2 in line: not a closed-form arm (Detect)
  const Vector3d e = Across(P3.w);
  double as[2];
  const int count = ShoulderAngles(X, w, M, center, free[0], as, free_mask);
  for (int i = 0; i < count; ++i) {
    const double a = as[i];
    const CosSin cs_a = CosSin::Of(a);
    const Isometry3d XM = Exp(X, cs_a.Negated()) * M;  // E_X(-a) M
    // The triple keeps w: R_Y(y) R_Z(z) (R_M^T R_X(a) w) = w; y is free where w lies on Y (the wrist
    // singularity of the UR family: axes 4 and 6 in line), z where v lies on Z.
    const Vector3d v = M.linear().transpose() * Rot(X.w, cs_a) * w;
    int wrist = 0;
    const AnglePairs pairs = Subproblem2(Y.w, Z.w, v, w, free[4], free[5], &wrist);
    *free_mask |= wrist << 4;
    for (int pair = 0; pair < pairs.size; ++pair) {
      auto [y, z] = pairs.pair[pair];
      // A free wrist angle moves the point of axis P3 (where the elbow must take it) on a circle in the
      // plane of the planar triple; only where that point is within the elbow's reach does it give a
      // solution, possibly at one angle alone (the elbow stretched there).
      CosSin cs_y = pairs.cs[pair][0], cs_z = pairs.cs[pair][1];
      if (pairs.free[pair] & 2) {
        z = elbow.ReachableFreeAngle(XM, Z, Exp(Y, -y) * P3.p, free[5]);
        cs_z = CosSin::Of(z);
      } else if (pairs.free[pair] & 1) {
        y = elbow.ReachableFreeAngle(XM * Exp(Z, -z), Y, P3.p, free[4]);
        cs_y = CosSin::Of(y);
      }
      const Isometry3d P = XM * Exp(Z, cs_z.Negated()) * Exp(Y, cs_y.Negated());
      const Vector3d P_e = P.linear() * e;
      // Elbow: the point of axis P3 goes from s to t by turns about P2 then P1 (circle intersection).
      const Vector3d s = P3.p, t = P * P3.p;
      const double r1 = elbow.Flat(t - P1.p).norm();
      const double along = (r1 * r1 - r2 * r2 + dist * dist) / (2 * dist);
      double h2 = r1 * r1 - along * along;
      if (h2 < -1e-9 * (r1 * r1 + 1e-12)) continue;
      h2 = std::max(h2, 0.0);
      for (double sign : {1.0, -1.0}) {
        const Vector3d x = c1 + along * dv / dist + sign * std::sqrt(h2) * w.cross(dv) / dist;
        Vector6d q;
        q[0] = a;
        q[4] = y;
        q[5] = z;
        CosSin cs_1, cs_2;
        q[2] = Subproblem1(P2.w, s - P2.p, x - c2, nullptr, &cs_2);
        bool free_1 = false;
        q[1] = Subproblem1(P1.w, x - c1, t - P1.p, &free_1, &cs_1);
        if (free_1) {
          // The elbow folded onto axis P1 (links of equal length): every turn about it does.
          q[1] = free[1];
          cs_1 = CosSin::Of(q[1]);
          *free_mask |= 2;
        }
        q[3] = Subproblem1(P3.w, e, Rot(P2.w, cs_2).transpose() * (Rot(P1.w, cs_1).transpose() * P_e));
        out->Push(q);
        if (h2 == 0.0) break;  // one elbow
      }
    }
  }
}

BranchList NominalInverseKinematics::Impl::Branches(const Isometry3d& T, const VectorXd& free, int* free_mask) const {
  *free_mask = 0;
  BranchList out;
  if (kind == Kind::kNumeric) return out;
  const Isometry3d M = (reversed ? T.inverse() : T) * T0.inverse();
  // The reversed chain has the same joint angles in reverse order (see Detect).
  Vector6d chain_free = free;
  if (reversed) chain_free.reverseInPlace();
  int mask = 0;
  if (kind == Kind::kPieper) {
    PieperBranches(M, chain_free, &out, &mask);
  } else {
    ParallelBranches(M, chain_free, &out, &mask);
  }
  if (reversed) {
    for (int b = 0; b < out.size; ++b) out.item[b].reverseInPlace();
    int reversed_mask = 0;
    for (int j = 0; j < n; ++j) {
      if (mask & (1 << j)) reversed_mask |= 1 << (n - 1 - j);
    }
    mask = reversed_mask;
  }
  *free_mask = mask;
  return out;
}

void NominalInverseKinematics::Impl::Polish(const Isometry3d& T, VectorXd* q, double* pe, double* oe,
                                            Matrix6Xd* jacobian) const {
  const KinematicModel& model = robot.model();
  // The pose and the Jacobian of each iterate from one pass of the model (the Jacobian of the last one
  // goes to the singularity test).
  Matrix6Xd J, J_trial;
  Vector6d e = PoseError(PoseAndJointJacobian(model, *q, &J), T);
  double cost = e.squaredNorm();
  for (int it = 0; it < 8 && cost > 1e-28; ++it) {
    // Closed-form branches exist for 6 joints only (Detect): fixed 6 x 6 normal equations, with a
    // damping at rounding level that keeps a singular J's system positive definite.
    DampedNormalEquations<6> normal;
    normal.Assemble(Matrix6d(J), e);
    if (!normal.Factor(1e-14 * std::max(1.0, normal.H().diagonal().maxCoeff()))) break;
    const Vector6d step = normal.Step();
    if (!step.allFinite()) break;
    const VectorXd trial = *q + step;
    const Vector6d e_trial = PoseError(PoseAndJointJacobian(model, trial, &J_trial), T);
    if (!(e_trial.squaredNorm() < cost)) break;
    *q = trial;
    e = e_trial;
    J.swap(J_trial);
    cost = e.squaredNorm();
  }
  *pe = e.head<3>().norm();
  *oe = e.tail<3>().norm();
  if (jacobian) jacobian->swap(J);
}

bool NominalInverseKinematics::Impl::Singular(const VectorXd& q, const Matrix6Xd* jacobian) const {
  Matrix6Xd computed;
  const Matrix6Xd& J = jacobian ? *jacobian : (computed = robot.model().JointJacobian(q));
  if (J.cols() < 6) return true;
  if (J.cols() == 6) {
    // r = sigma_min / sigma_max is bracketed without an SVD: sigma_max <= |J|_F <= sqrt(6) sigma_max and
    // 1 / sigma_min <= |J^-1|_F <= sqrt(6) / sigma_min give r / 6 <= 1 / (|J|_F |J^-1|_F) <= r. Only a
    // ratio inside that factor of 6 of the threshold (or an exactly singular LU) needs the SVD.
    const Matrix6d A = J;
    const double bound = 1.0 / (A.norm() * InverseNorm(A));
    if (bound >= options.singular_ratio) return false;
    if (6 * bound < options.singular_ratio) return true;
  }
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
  return s[s.size() - 1] < options.singular_ratio * s[0];
}

bool NominalInverseKinematics::Impl::MatchesConfiguration(const Eigen::Ref<const VectorXd>& q) const {
  for (size_t j = 0; j < options.configuration.size(); ++j) {
    const double v = WrapAngle(q[j]);
    if ((options.configuration[j] > 0 && v < 0) || (options.configuration[j] < 0 && v > 0)) return false;
  }
  return true;
}

IkSolution NominalInverseKinematics::Impl::Numeric(const Isometry3d& T, bool orientation, const VectorXd& reference,
                                                   const VectorXd& start, int restarts) const {
  InverseKinematicsOptions numeric = options.numeric;
  if (restarts >= 0) numeric.restarts = restarts;
  const InverseKinematicsResult r =
      SolveInverseKinematics(robot, T, orientation, start.size() == n ? start : reference, numeric);
  IkSolution s;
  s.q = r.q.allFinite() ? r.q : reference;
  s.position_error = std::isfinite(r.position_error) ? r.position_error : INFINITY;
  s.orientation_error = std::isfinite(r.orientation_error) ? r.orientation_error : INFINITY;
  const bool reached = s.position_error <= options.position_tolerance &&
                       (!orientation || s.orientation_error <= options.orientation_tolerance);
  // Not reached by any start: unreachable, whatever the configuration of the least error (next to a
  // pose out of reach it is the arm stretched towards it, singular).
  if (!reached) {
    s.status = IkStatus::kUnreachable;
    return s;
  }
  VectorXd q = s.q;
  const bool inside = WrapIntoLimits(reference, q);
  s.q = q;
  s.status = !inside ? IkStatus::kOutOfLimits : (orientation && Singular(q)) ? IkStatus::kSingular : IkStatus::kSolved;
  return s;
}

NominalInverseKinematics::NominalInverseKinematics(const Robot& robot, const NominalIkOptions& options)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("inverse kinematics: " + OneLine(why));
  if (!robot.has_model()) throw std::invalid_argument("inverse kinematics: the robot has no model");
  impl_->robot = robot;
  impl_->options = options;
  impl_->n = robot.dof();
  if (!options.configuration.empty() && static_cast<int>(options.configuration.size()) != impl_->n) {
    throw std::invalid_argument("inverse kinematics: configuration needs one sign per joint");
  }
  impl_->middle.resize(impl_->n);
  for (int j = 0; j < impl_->n; ++j) {
    const auto [low, high] = robot.Limit(j);
    impl_->middle[j] = 0.5 * (low + high);
  }
  impl_->Detect();
}

NominalInverseKinematics::~NominalInverseKinematics() = default;

std::string NominalInverseKinematics::method() const {
  const int a = impl_->reversed ? impl_->n - impl_->first - 2 : impl_->first + 1;
  const std::string joints = std::to_string(a) + "," + std::to_string(a + 1) + "," + std::to_string(a + 2) + ")";
  switch (impl_->kind) {
    case Impl::Kind::kPieper:
      return "pieper(" + joints;
    case Impl::Kind::kParallel:
      return "parallel(" + joints;
    case Impl::Kind::kNumeric:
      break;
  }
  return "numeric";
}

bool NominalInverseKinematics::has_closed_form() const { return impl_->kind != Impl::Kind::kNumeric; }

bool NominalInverseKinematics::Impl::Choose(const Isometry3d& T, const VectorXd& ref, BranchList* branches,
                                            IkSolution* s, VectorXd* unfinished) const {
  if (unfinished) unfinished->resize(0);
  // Rank: inside the limits, then the named configuration, then the distance to the reference.
  struct Candidate {
    int rank;
    double distance;
    int branch;
  };
  Candidate candidates[BranchList::kCapacity];
  int count = 0;
  for (int b = 0; b < branches->size; ++b) {
    Vector6d& q = branches->item[b];
    if (!q.allFinite()) continue;
    const bool inside = WrapIntoLimits(ref, q);
    const int rank = (inside ? 0 : 2) + (MatchesConfiguration(q) ? 0 : 1);
    candidates[count++] = {rank, (q - ref).squaredNorm(), b};
  }
  std::sort(candidates, candidates + count, [](const Candidate& a, const Candidate& b) {
    return a.rank != b.rank ? a.rank < b.rank : a.distance < b.distance;
  });
  // The first candidate that reaches the pose inside the limits. One ranked inside before the polish may
  // end outside after it (next to a singular configuration the polish can move far): then the next
  // candidates, with the first that reached as the fallback.
  bool reached_outside = false;
  IkSolution fallback;
  for (int c = 0; c < count; ++c) {
    IkSolution t;
    t.q = branches->item[candidates[c].branch];
    t.branch = candidates[c].branch;
    t.closed_form = true;
    Matrix6Xd J;
    Polish(T, &t.q, &t.position_error, &t.orientation_error, &J);
    const Vector6d polished = t.q;
    if (!(t.position_error <= options.position_tolerance && t.orientation_error <= options.orientation_tolerance)) {
      if (unfinished && unfinished->size() == 0 && candidates[c].rank < 2) *unfinished = t.q;
      continue;
    }
    bool clamped = false;
    const bool inside = WrapIntoLimits(ref, t.q, &clamped);
    if (clamped) {
      // On a limit: the errors of the joints as returned.
      const Vector6d e = PoseError(robot.model().ForwardKinematics(t.q), T);
      t.position_error = e.head<3>().norm();
      t.orientation_error = e.tail<3>().norm();
      if (!(t.position_error <= options.position_tolerance && t.orientation_error <= options.orientation_tolerance)) {
        continue;
      }
    }
    if (inside) {
      // The polish's Jacobian unless the joints moved since (whole turns or a clamp).
      t.status = Singular(t.q, t.q == polished ? &J : nullptr) ? IkStatus::kSingular : IkStatus::kSolved;
      *s = t;
      return true;
    }
    t.status = IkStatus::kOutOfLimits;
    if (!reached_outside) fallback = t;
    reached_outside = true;
    if (candidates[c].rank >= 2) break;  // the rest were outside before the polish too
  }
  if (reached_outside) *s = fallback;
  return reached_outside;
}

bool NominalInverseKinematics::Impl::SearchFamily(const Isometry3d& T, const VectorXd& ref, int free_mask,
                                                  IkSolution* s) const {
  // Whether a raw branch with free joint j at t reaches the pose (to the closed form's rounding, before the
  // polish) inside the limits; `strict`: without the slack that clamps a joint on a limit (the bisection
  // then ends inside, where the polished solution needs no clamp that would cost pose accuracy).
  VectorXd free = ref;
  const auto inside_at = [&](int j, double t, bool strict) {
    free[j] = t;
    int mask = 0;
    const BranchList branches = Branches(T, free, &mask);
    free[j] = ref[j];
    for (int b = 0; b < branches.size; ++b) {
      Vector6d q = branches.item[b];
      bool clamped = false;
      if (!q.allFinite() || !WrapIntoLimits(ref, q, &clamped) || (strict && clamped)) continue;
      const Vector6d e = PoseError(robot.model().ForwardKinematics(q), T);
      if (e.head<3>().norm() <= 1e-6 && e.tail<3>().norm() <= 1e-6) return true;
    }
    return false;
  };
  // Samples every 2 pi / 16 outwards from the reference's value, both ways; at the first inside, the
  // edge of the limits between it and the sample before (outside), by bisection to ~4e-13 rad.
  constexpr int kSamples = 16;
  constexpr double kStep = 2 * M_PI / kSamples;
  int best_joint = -1;
  double best_shift = INFINITY;
  for (int j = 0; j < n; ++j) {
    if (!(free_mask & (1 << j))) continue;
    bool found = false;
    for (int k = 1; k <= kSamples / 2 && !found; ++k) {
      for (double sign : {1.0, -1.0}) {
        if (k == kSamples / 2 && sign < 0) continue;  // the same sample as +pi
        if (k * kStep > std::abs(best_shift) + kStep) break;
        if (!inside_at(j, ref[j] + sign * k * kStep, false)) continue;
        found = true;
        double outside = sign * (k - 1) * kStep, inside = sign * k * kStep;
        for (int it = 0; it < 40; ++it) {
          const double mid = 0.5 * (outside + inside);
          (inside_at(j, ref[j] + mid, true) ? inside : outside) = mid;
        }
        if (std::abs(inside) < std::abs(best_shift)) {
          best_shift = inside;
          best_joint = j;
        }
      }
    }
  }
  if (best_joint < 0) return false;
  free[best_joint] = ref[best_joint] + best_shift;
  int mask = 0;
  BranchList branches = Branches(T, free, &mask);
  return Choose(T, ref, &branches, s) && s->status != IkStatus::kOutOfLimits;
}

std::vector<IkSolution> NominalInverseKinematics::AllBranches(const Isometry3d& T, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd& ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  std::vector<IkSolution> out;
  int free_mask = 0;
  const BranchList branches = m.Branches(T, ref, &free_mask);
  for (int b = 0; b < branches.size; ++b) {
    IkSolution s;
    s.q = branches.item[b];
    if (!s.q.allFinite()) continue;
    s.branch = b;
    s.closed_form = true;
    m.Polish(T, &s.q, &s.position_error, &s.orientation_error);
    if (!(s.position_error <= m.options.position_tolerance && s.orientation_error <= m.options.orientation_tolerance))
      continue;
    const bool inside = m.WrapIntoLimits(ref, s.q);
    s.status = !inside ? IkStatus::kOutOfLimits : m.Singular(s.q) ? IkStatus::kSingular : IkStatus::kSolved;
    bool duplicate = false;
    for (const IkSolution& o : out) {
      VectorXd d = o.q - s.q;
      for (int j = 0; j < m.n; ++j) d[j] = WrapAngle(d[j]);
      duplicate = duplicate || d.cwiseAbs().maxCoeff() < 1e-6;
    }
    if (!duplicate) out.push_back(s);
  }
  return out;
}

IkSolution NominalInverseKinematics::Solve(const Isometry3d& T, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd& ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  int free_mask = 0;
  BranchList branches = m.Branches(T, ref, &free_mask);
  IkSolution s;
  VectorXd unfinished;
  const bool reached = m.Choose(T, ref, &branches, &s, &unfinished);
  if (reached && s.status != IkStatus::kOutOfLimits) return s;
  // A continuum of solutions whose member with the free joint at the reference leaves the limits: the
  // free joint moves as little as the limits require.
  IkSolution inside;
  if (reached && free_mask != 0 && m.SearchFamily(T, ref, free_mask, &inside)) return inside;
  // A candidate inside the limits that the polish could not finish: within about 1e-8 rad of a singular
  // configuration, where the closed form's free member (or its general solution) misses by ~1e-9.
  // The numeric solver, from there.
  if (unfinished.size() == m.n) {
    inside = m.Numeric(T, true, ref, unfinished, 0);
    if (inside.status == IkStatus::kSolved || inside.status == IkStatus::kSingular) return inside;
  }
  if (reached) return s;
  // No closed form, or no branch reaches the pose (out of reach, or rounding at the edge): numeric.
  return m.Numeric(T, true, ref);
}

IkSolution NominalInverseKinematics::SolvePosition(const Vector3d& p, const VectorXd& reference) const {
  const Impl& m = *impl_;
  const VectorXd ref = reference.size() == m.n && reference.allFinite() ? reference : m.middle;
  Isometry3d T = Isometry3d::Identity();
  T.translation() = p;
  return m.Numeric(T, false, ref);
}

}  // namespace kincal
