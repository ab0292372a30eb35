#include "studies/validation.h"

#include <algorithm>
#include <cmath>

#include "framework/error.h"
#include "robot/inverse_kinematics.h"
#include "framework/math.h"
#include "robot/nominal_ik.h"
#include "framework/random.h"
#include "framework/svd.h"

namespace kincal {

std::vector<ValidationTarget> RandomTargets(const Robot& nominal, int count,
                                            const std::vector<std::pair<double, double>>& limits, uint64_t seed) {
  const int n = nominal.dof();
  Rng rng(seed);
  std::vector<ValidationTarget> targets;
  targets.reserve(count);
  for (int k = 0; k < count; ++k) {
    ValidationTarget t;
    t.q_nominal.resize(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = limits.empty() ? nominal.Limit(j) : limits[j];
      t.q_nominal[j] = rng.Uniform(low, high);
    }
    t.T_meas_tool = nominal.model().ForwardKinematics(t.q_nominal);
    targets.push_back(std::move(t));
  }
  return targets;
}

std::vector<ValidationTarget> ReachableRandomTargets(const Robot& nominal, const Robot& truth, int count,
                                                     const std::vector<std::pair<double, double>>& limits,
                                                     bool orientation, uint64_t seed) {
  const int n = nominal.dof();
  const NominalInverseKinematics ik(nominal);
  Rng rng(seed);
  std::vector<ValidationTarget> targets;
  targets.reserve(count);
  long rejected = 0;
  while (static_cast<int>(targets.size()) < count) {
    if (rejected > 100L * (count + 10)) {
      ThrowInputError("random targets: the nominal robot reaches almost none of the real arm's poses");
    }
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = limits.empty() ? truth.Limit(j) : limits[j];
      q[j] = rng.Uniform(low, high);
    }
    ValidationTarget t;
    t.T_meas_tool = truth.model().ForwardKinematics(q);
    const IkSolution s = orientation ? ik.Solve(t.T_meas_tool, q) : ik.SolvePosition(t.T_meas_tool.translation(), q);
    bool ok = s.status == IkStatus::kSolved;
    for (int j = 0; ok && j < n && !limits.empty(); ++j) ok = s.q[j] >= limits[j].first && s.q[j] <= limits[j].second;
    if (!ok) {
      ++rejected;
      continue;
    }
    // The controller commands readings; its coupling (if any) maps them to the model's joints.
    t.q_nominal = nominal.coupling.size() ? Eigen::VectorXd(nominal.coupling.inverse() * s.q) : s.q;
    targets.push_back(std::move(t));
  }
  return targets;
}

std::array<Eigen::Vector3d, 5> Iso9283Points(const Eigen::Vector3d& center, double side) {
  // The diagonal plane through the two cube edges parallel to z at (-x, -y) and (+x, +y).
  const double h = side / 2;
  const Eigen::Vector3d corners[4] = {{-h, -h, h}, {h, h, h}, {h, h, -h}, {-h, -h, -h}};
  std::array<Eigen::Vector3d, 5> points;
  points[0] = center;
  for (int i = 0; i < 4; ++i) points[i + 1] = center + 0.8 * corners[i];
  return points;
}

namespace {

// Smallest singular value of the joint Jacobian, rotation rows scaled by a length so that both count.
double Dexterity(const Robot& robot, const Eigen::VectorXd& q, bool orientation, double length) {
  Matrix6Xd J = robot.model().JointJacobian(q);
  J.bottomRows<3>() *= length;
  const Eigen::MatrixXd A = orientation ? Eigen::MatrixXd(J) : Eigen::MatrixXd(J.topRows<3>());
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  return A.rows() > A.cols() ? 0.0 : s[s.size() - 1];
}

bool TryCube(const Robot& robot, const Eigen::VectorXd& q_center, double side, bool orientation, Iso9283Cube* cube) {
  const Eigen::Isometry3d T_center = robot.model().ForwardKinematics(q_center);
  const std::array<Eigen::Vector3d, 5> points = Iso9283Points(T_center.translation(), side);
  InverseKinematicsOptions ik;
  ik.restarts = 0;
  ik.max_iterations = 200;
  cube->poses.clear();
  for (const auto& p : points) {
    ValidationTarget t;
    t.T_meas_tool = T_center;
    t.T_meas_tool.translation() = p;
    const InverseKinematicsResult r = SolveInverseKinematics(robot, t.T_meas_tool, orientation, q_center, ik);
    if (!r.converged) return false;
    for (int j = 0; j < robot.dof(); ++j) {
      const auto [low, high] = robot.Limit(j);
      if (r.q[j] < low || r.q[j] > high || std::abs(r.q[j] - q_center[j]) > M_PI / 3) return false;
    }
    t.q_nominal = r.q;
    cube->poses.push_back(std::move(t));
  }
  cube->center_configuration = q_center;
  cube->center = T_center.translation();
  cube->side = side;
  return true;
}

}  // namespace

Iso9283Cube PlaceIso9283Cube(const Robot& nominal, const Iso9283Spec& spec, bool orientation, uint64_t seed) {
  Iso9283Cube cube;
  const int n = nominal.dof();
  if (spec.center_configuration.size() == n) {
    if (!TryCube(nominal, spec.center_configuration, spec.side, orientation, &cube)) {
      ThrowInputError("iso9283: the nominal robot cannot reach every pose of a " + std::to_string(spec.side * 1e3) +
                      " mm cube around center_configuration on one inverse-kinematics branch");
    }
    return cube;
  }
  // A deterministic sample in the middle 60 % of each joint's range, most dexterous first.
  Rng rng(seed);
  std::vector<Eigen::VectorXd> samples;
  std::vector<double> reach;
  for (int k = 0; k < 96; ++k) {
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = nominal.Limit(j);
      const double mid = 0.5 * (low + high), half = 0.3 * (high - low);
      q[j] = rng.Uniform(mid - half, mid + half);
    }
    reach.push_back((nominal.model().ForwardKinematics(q).translation() - nominal.model().base().translation()).norm());
    samples.push_back(q);
  }
  const double length = std::max(0.1, 0.5 * *std::max_element(reach.begin(), reach.end()));
  std::vector<std::pair<double, int>> order;
  for (size_t k = 0; k < samples.size(); ++k) {
    order.emplace_back(-Dexterity(nominal, samples[k], orientation, length), static_cast<int>(k));
  }
  std::sort(order.begin(), order.end());
  for (const auto& [score, k] : order) {
    if (TryCube(nominal, samples[k], spec.side, orientation, &cube)) return cube;
  }
  ThrowInputError("iso9283: found no placement of a " + std::to_string(spec.side * 1e3) +
                  " mm cube that the nominal robot reaches; give a smaller side or a center_configuration");
}

Iso9283PoseStats ComputeIso9283(const Eigen::Isometry3d& commanded, const std::vector<Eigen::Isometry3d>& attained) {
  Iso9283PoseStats s;
  const int n = static_cast<int>(attained.size());
  s.cycles = n;
  if (n < 2) throw std::invalid_argument("ISO 9283 statistics need at least 2 cycles");
  Eigen::Vector3d p_mean = Eigen::Vector3d::Zero(), abc_mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> abc(n);
  for (int j = 0; j < n; ++j) {
    p_mean += attained[j].translation();
    abc[j] = RotationLog(attained[j].linear() * commanded.linear().transpose());
    abc_mean += abc[j];
  }
  p_mean /= n;
  abc_mean /= n;
  s.ap_p = (p_mean - commanded.translation()).norm();
  s.ap_abc = abc_mean;
  std::vector<double> l(n);
  double l_mean = 0.0;
  for (int j = 0; j < n; ++j) {
    l[j] = (attained[j].translation() - p_mean).norm();
    l_mean += l[j];
  }
  l_mean /= n;
  double s_l = 0.0;
  Eigen::Vector3d s_abc = Eigen::Vector3d::Zero();
  for (int j = 0; j < n; ++j) {
    s_l += (l[j] - l_mean) * (l[j] - l_mean);
    s_abc += (abc[j] - abc_mean).cwiseAbs2();
  }
  s.rp_l = l_mean + 3.0 * std::sqrt(s_l / (n - 1));
  s.rp_abc = 3.0 * (s_abc / (n - 1)).cwiseSqrt();
  return s;
}

}  // namespace kincal
