#include "compensators/joint_space/joint_space_compensator.h"

#include <chrono>
#include <cmath>

#include "compensators/common/random_targets.h"
#include "compensators/jacobian/jacobian_compensator.h"
#include "framework/random.h"
#include "framework/units.h"

namespace kincal {
namespace {

// dq(q_nom) = q_id - q_nom; false when the solve did not converge.
bool Correction(const Compensator& solver, const Robot& nominal, const Eigen::VectorXd& q_nom, Eigen::VectorXd* dq) {
  CompensationTarget target;
  target.T_meas_tool = nominal.model().ForwardKinematics(q_nom);
  target.seed = q_nom;
  const CompensationResult result = solver.Compensate(target);
  *dq = result.q_actual - q_nom;
  return result.report.status == CompensationStatus::kConverged;
}

// Joints whose change alters the correction, probed at a few well-conditioned random configurations.
std::vector<int> JointsThatMatter(const Compensator& solver, const Robot& nominal, double tolerance) {
  const int n = nominal.dof();
  std::vector<bool> matters(n, false);
  Rng rng(20150731);
  const auto random_joints = [&](Eigen::VectorXd* q) {
    for (int j = 0; j < n; ++j) {
      const auto [low, high] = nominal.Limit(j);
      (*q)[j] = rng.Uniform(low, high);
    }
  };
  int samples = 0;
  for (int attempt = 0; attempt < 200 && samples < 6; ++attempt) {
    Eigen::VectorXd q(n), dq0, dq1;
    random_joints(&q);
    if (JacobianConditionRatio(nominal.model(), q, 0.5) < 0.02 || !Correction(solver, nominal, q, &dq0)) continue;
    ++samples;
    for (int j = 0; j < n; ++j) {
      if (matters[j]) continue;
      Eigen::VectorXd moved = q;
      const auto [low, high] = nominal.Limit(j);
      moved[j] = rng.Uniform(low, high);
      // A move that fails to converge or lands near a singularity says nothing; count the joint in.
      if (JacobianConditionRatio(nominal.model(), moved, 0.5) < 0.02 || !Correction(solver, nominal, moved, &dq1) ||
          (dq1 - dq0).lpNorm<Eigen::Infinity>() > tolerance) {
        matters[j] = true;
      }
    }
  }
  std::vector<int> joints;
  for (int j = 0; j < n; ++j) {
    if (matters[j] || samples == 0) joints.push_back(j + 1);
  }
  return joints;
}

}  // namespace

JointSpaceCompensator::JointSpaceCompensator() : JointSpaceCompensator(Options()) {}

bool JointSpaceCompensator::Options::IsValid(std::string* why) const {
  const auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  for (size_t i = 0; i < joints.size(); ++i) {
    if (joints[i] < 1) return fail("joints are 1-based");
    for (size_t k = 0; k < i; ++k) {
      if (joints[k] == joints[i]) return fail("a joint is listed twice");
    }
  }
  if (points < 2) return fail("points must be >= 2");
  if (interpolation != "linear" && interpolation != "cubic") return fail("interpolation must be linear or cubic");
  if (!(max_correction > 0)) return fail("max_correction must be > 0");
  if (!(invariance_tolerance > 0)) return fail("invariance_tolerance must be > 0");
  if (!(max_table_bytes > 0)) return fail("max_table_bytes must be > 0");
  return true;
}

JointSpaceCompensator::Options JointSpaceCompensator::Options::FromYaml(const YAML::Node& node) {
  Options o;
  OptionsReader reader(node, "joint_space");
  std::vector<std::string> joints;
  reader.Get("joints", &joints);
  if (!(joints.size() == 1 && joints[0] == "auto")) {
    for (const auto& j : joints) {
      double v = 0;
      if (!ParseDouble(j, &v) || v != std::floor(v)) reader.Fail("joints", "expected 1-based joint numbers or auto");
      o.joints.push_back(static_cast<int>(v));
    }
  }
  reader.Get("points", &o.points);
  reader.Get("interpolation", &o.interpolation);
  reader.Get("max_correction", &o.max_correction);
  reader.Get("invariance_tolerance", &o.invariance_tolerance);
  reader.Get("max_table_bytes", &o.max_table_bytes);
  reader.Finish();
  return o;
}

void JointSpaceCompensator::DoPrepare() {
  const auto t0 = std::chrono::steady_clock::now();
  const Robot& nom = nominal();
  const int n = nom.dof();
  interpolation_ = options_.interpolation == "linear" ? CorrectionTable::Interpolation::kLinear
                                                      : CorrectionTable::Interpolation::kCubic;
  // Near singular configurations the exact solution can lie far along the near-null direction, on
  // another branch than the neighbouring nodes; small trust steps keep the solve next to q_nom, and
  // max_correction flags what still wanders.
  JacobianCompensator::Options solver_options;
  solver_options.iteration.trust_radius = 0.02;
  solver_options.iteration.max_iterations = 12;  // 0.24 rad at most: beyond max_correction anyway
  JacobianCompensator solver(solver_options);
  solver.Prepare(nominal(), identified());

  std::vector<int> joints = options_.joints;
  for (int j : joints) {
    if (j > n) throw std::invalid_argument("joint_space: joint " + std::to_string(j) + " of a " + std::to_string(n) + "-joint robot");
  }
  if (joints.empty()) joints = JointsThatMatter(solver, nom, options_.invariance_tolerance);

  std::vector<CorrectionTable::Axis> axes;
  for (int j : joints) {
    const auto [low, high] = nom.Limit(j - 1);
    axes.push_back({j - 1, low, high, options_.points});
  }
  const double bytes = CorrectionTable::MemoryBytes(axes, n);
  if (bytes > options_.max_table_bytes) {
    throw std::invalid_argument("joint_space: a table over " + std::to_string(joints.size()) + " joints with " +
                                std::to_string(options_.points) + " points each needs " + std::to_string(bytes / 1e6) +
                                " MB, over max_table_bytes");
  }
  table_ = CorrectionTable(axes, n);

  // Joints off the grid sit at 0 (or mid-range when 0 is outside their limits) while tabulating.
  Eigen::VectorXd q(n), dq;
  for (int j = 0; j < n; ++j) {
    const auto [low, high] = nom.Limit(j);
    q[j] = (low <= 0.0 && 0.0 <= high) ? 0.0 : 0.5 * (low + high);
  }
  for (int64_t node = 0; node < table_.num_nodes(); ++node) {
    table_.NodeJoints(node, &q);
    if (!Correction(solver, nom, q, &dq) || dq.lpNorm<Eigen::Infinity>() > options_.max_correction) {
      table_.Flag(node);
    }
    std::copy(dq.data(), dq.data() + n, table_.values(node));
  }
  info_.joints = joints;
  info_.points = options_.points;
  info_.nodes = table_.num_nodes();
  info_.memory_bytes = table_.memory_bytes();
  info_.unconverged_nodes = table_.num_flagged();
  info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void JointSpaceCompensator::DoCompensate(const CompensationTarget& /*target*/, const Eigen::VectorXd& seed,
                                         CompensationResult* result) const {
  result->q_actual.resize(seed.size());
  const CorrectionTable::Lookup lookup = table_.Interpolate(seed, interpolation_, result->q_actual.data());
  result->q_actual += seed;
  result->report.iterations = 0;
  if (!lookup.inside) {
    result->report.status = CompensationStatus::kFailed;
    result->report.message = "seed outside the table: correction of the nearest edge";
  } else if (lookup.flagged) {
    result->report.status = CompensationStatus::kSingular;
    result->report.message = "table cell next to an unconverged node (singular configuration)";
  } else {
    result->report.status = CompensationStatus::kConverged;
  }
}

}  // namespace kincal
