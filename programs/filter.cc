#include "programs/filter.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "compensators/program.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal {

namespace {

constexpr double kDeg = M_PI / 180.0;

// [x, y, z, a, b, c] in mm and deg of a transform (inverse of PoseFromXyzAbc), for the documentation.
std::vector<double> XyzAbc(const Eigen::Isometry3d& T) {
  // + 0.0: no "-0" in the documentation.
  const Eigen::Vector3d abc = (T.linear().eulerAngles(2, 1, 0) / kDeg).array() + 0.0;
  const Eigen::Vector3d xyz = (T.translation() * 1e3).array() + 0.0;
  return {xyz.x(), xyz.y(), xyz.z(), abc[0], abc[1], abc[2]};
}

std::string FinitePose(const Eigen::Isometry3d& T, const char* what) {
  return T.matrix().allFinite() ? std::string() : std::string(what) + " must be finite";
}

// The point of axis 1 nearest axis 2 at q = 0 (where they meet, on arms like the IRB 120), in the
// measurement frame: the centre the arm's reach is measured from. Axes from the joint screws: the tool
// point p moves at v = w x (p - a) about an axis through a, so p + w x v / |w|^2 lies on it.
Eigen::Vector3d Shoulder(const Robot& robot) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(robot.dof());
  const Eigen::Vector3d p = robot.model().ForwardKinematics(zero).translation();
  if (robot.dof() < 2) return robot.model().base().translation();
  const Matrix6Xd J = robot.model().JointJacobian(zero);
  const Eigen::Vector3d w1 = J.col(0).tail<3>(), w2 = J.col(1).tail<3>();
  if (!(w1.squaredNorm() > 0) || !(w2.squaredNorm() > 0)) return robot.model().base().translation();
  const Eigen::Vector3d a1 = p + w1.cross(J.col(0).head<3>()) / w1.squaredNorm();
  const Eigen::Vector3d a2 = p + w2.cross(J.col(1).head<3>()) / w2.squaredNorm();
  const Eigen::Vector3d n = w1.cross(w2);
  if (n.squaredNorm() < 1e-12 * w1.squaredNorm() * w2.squaredNorm()) return a1;
  return a1 + w1 * ((a2 - a1).cross(w2).dot(n) / n.squaredNorm());
}

}  // namespace

Eigen::Isometry3d PoseFromXyzAbc(const std::vector<double>& v) {
  if (v.size() != 6) throw std::invalid_argument("expected 6 numbers [x, y, z, a, b, c] (mm, deg)");
  for (double x : v) {
    if (!std::isfinite(x)) throw std::invalid_argument("expected 6 finite numbers [x, y, z, a, b, c] (mm, deg)");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]) * 1e-3;
  T.linear() = (Eigen::AngleAxisd(v[3] * kDeg, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4] * kDeg, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[5] * kDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

const OptionTable<FilterOptions>& FilterOptions::Table() {
  using O = FilterOptions;
  static const OptionTable<O> table =
      OptionTable<O>("filter")
          .Add<std::vector<double>>(
              "work_object", [](const O& o) { return XyzAbc(o.T_base_frame); },
              [](O* o, const std::vector<double>& v) { o->T_base_frame = PoseFromXyzAbc(v); },
              "the program's frame in the robot's base frame, [x, y, z, a, b, c] (mm, deg)")
          .Add<std::vector<double>>(
              "tool", [](const O& o) { return o.T_flange_tool ? XyzAbc(*o.T_flange_tool) : std::vector<double>(); },
              [](O* o, const std::vector<double>& v) {
                if (v.empty()) {
                  o->T_flange_tool.reset();
                } else {
                  o->T_flange_tool = PoseFromXyzAbc(v);
                }
              },
              "the targets' tool, flange to tool, [x, y, z, a, b, c] (mm, deg); [] the robot file's")
          .Add("keep_tolerance", &O::keep_tolerance,
               "a number that moves by no more than this (relative to max(1, |value|)) keeps its text", NonNegative())
          .Rule({"work_object"}, [](const O& o) { return FinitePose(o.T_base_frame, "the work object"); })
          .Rule({"tool"},
                [](const O& o) { return o.T_flange_tool ? FinitePose(*o.T_flange_tool, "the tool") : std::string(); });
  return table;
}

bool FilterOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

ProgramFilter::ProgramFilter(const Robot& nominal, const Robot& identified, std::unique_ptr<Compensator> compensator,
                             const FilterOptions& options, ConfigurationConvention convention)
    : options_(options), compensator_(std::move(compensator)) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("filter: " + why);
  Robot nominal_used = nominal, identified_used = identified;
  if (options_.T_flange_tool) {
    identified_used.model().SetTool(*options_.T_flange_tool);
    if (!nominal.model().tool().matrix().isIdentity(0.0)) nominal_used.model().SetTool(*options_.T_flange_tool);
  }
  compensator_->Prepare(nominal_used, identified_used);
  controller_ = ControllerRobot(nominal_used, identified_used);
  ik_ = std::make_unique<NominalInverseKinematics>(controller_);
  shoulder_ = Shoulder(controller_);
  rules_ = std::make_unique<ConfigurationRules>(convention, controller_);
}

Eigen::VectorXd ProgramFilter::RealArmSeed(const CompensationTarget& goal, const std::vector<int>& configuration,
                                           const Eigen::VectorXd& reference) const {
  const int n = controller_.dof();
  Eigen::VectorXd middle(n);
  for (int j = 0; j < n; ++j) middle[j] = 0.5 * (controller_.Limit(j).first + controller_.Limit(j).second);
  const Eigen::VectorXd& ref = reference.size() == n ? reference : middle;
  // The real arm's joints from `start` when they have the named configuration; empty otherwise.
  const auto from = [&](const Eigen::VectorXd& start) -> Eigen::VectorXd {
    CompensationTarget t = goal;
    t.seed = start;
    const CompensationResult r = compensator_->Compensate(t);
    const bool named = r.report.status == CompensationStatus::kConverged && rules_->Of(r.q_command) == configuration;
    return named ? r.q_command : Eigen::VectorXd();
  };
  // First the controller's solutions on the named branch of the target moved towards the shoulder (into
  // the nominal arm's reach next to the stretched elbow; the real arm's solution is nearby).
  for (double pull : {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2}) {
    const Eigen::Vector3d towards = shoulder_ - goal.T_meas_tool.translation();
    if (!(towards.norm() > pull)) break;
    Eigen::Isometry3d pulled = goal.T_meas_tool;
    pulled.translation() += pull * towards.normalized();
    const ConfigurationRules::Solution s = rules_->Solve(*ik_, pulled, configuration, reference);
    if (!s.found) continue;
    const Eigen::VectorXd q = from(s.q);
    if (q.size()) return q;
  }
  // Then random moves of the controller's closest attempt and of each of its branches of the target (next
  // to a singular wrist, the real arm's q5 can have the other sign than every nominal solution's), with a
  // spread growing to pi; draws that do not fit the named fields by whole turns are drawn again.
  std::vector<Eigen::VectorXd> bases = {ik_->Solve(goal.T_meas_tool, ref).q};
  for (const IkSolution& b : ik_->AllBranches(goal.T_meas_tool, ref)) bases.push_back(b.q);
  constexpr int kSpreads = 24, kDraws = 200, kMaxStarts = 64;
  Rng rng(1);  // a fixed stream: the same target gives the same joints
  int starts = 0;
  for (int k = 0; k < kSpreads; ++k) {
    const double spread = 0.02 * std::pow(M_PI / 0.02, k / (kSpreads - 1.0));
    for (const Eigen::VectorXd& base : bases) {
      Eigen::VectorXd q;
      bool fits = false;
      for (int draw = 0; draw < kDraws && !fits; ++draw) {
        Eigen::VectorXd start = base;
        for (int j = 0; j < n; ++j) start[j] += rng.Uniform(-spread, spread);
        fits = rules_->Fit(start, configuration, ref, &q);
      }
      if (!fits) continue;
      const Eigen::VectorXd solution = from(q);
      if (solution.size()) return solution;
      if (++starts == kMaxStarts) return {};
    }
  }
  return {};
}

std::string ReplaceNumbers(const std::string& text, const std::vector<NumberSpan>& spans,
                           const std::vector<double>& values, double keep_tolerance) {
  std::vector<size_t> order(spans.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return spans[a].begin < spans[b].begin; });
  std::string out;
  out.reserve(text.size() + text.size() / 4);
  size_t at = 0;
  for (size_t k : order) {
    const NumberSpan& s = spans[k];
    const double v = values[k];
    out.append(text, at, s.begin - at);
    at = s.end;
    if (s.integer) {
      const long long i = std::llround(v);
      if (i == std::llround(s.value)) {
        out.append(text, s.begin, s.end - s.begin);
      } else if (s.binary) {  // 'B0110': as many digits as written, more if needed
        std::string bits;
        for (long long r = i; r > 0; r >>= 1) bits.insert(bits.begin(), static_cast<char>('0' + (r & 1)));
        const size_t digits = s.end - s.begin - 3;  // without 'B and '
        if (bits.size() < digits) bits.insert(0, digits - bits.size(), '0');
        out += "'B" + bits + "'";
      } else {
        out += std::to_string(i);
      }
      continue;
    }
    if (std::abs(v - s.value) <= keep_tolerance * std::max(1.0, std::abs(s.value))) {
      out.append(text, s.begin, s.end - s.begin);
    } else {
      out += FormatNumber(v);
    }
  }
  out.append(text, at, std::string::npos);
  return out;
}

FilteredProgram ProgramFilter::Filter(const ProgramFormat& format, const std::string& text,
                                      const std::string& path) const {
  const std::vector<ProgramTarget> targets = format.Read(text, path);
  FilteredProgram out;
  FilterReport& report = out.report;
  std::vector<NumberSpan> spans;
  std::vector<double> values;
  const Eigen::Isometry3d T_meas_frame = controller_.model().base() * options_.T_base_frame;
  const Eigen::Isometry3d T_frame_meas = T_meas_frame.inverse();
  Eigen::VectorXd reference;  // the controller's joints at the previous target
  const auto keep = [&](const ProgramTarget& target, const std::string& why) {
    report.not_reached.push_back(path + ":" + std::to_string(target.line) + ": " + why);
    out.commands.emplace_back();
  };
  // The goal of a target: the pose in the measurement frame and the controller's joints for it.
  const auto build = [&](size_t i, CompensationTarget* goal) {
    const ProgramTarget& target = targets[i];
    const bool pose = target.kind == ProgramTarget::Kind::kPose;
    (pose ? report.pose_targets : report.joint_targets)++;
    if (!pose) {
      goal->T_meas_tool = controller_.model().ForwardKinematics(
          controller_.coupling.size() ? Eigen::VectorXd(controller_.coupling * target.q) : target.q);
      goal->seed = target.q;
      return true;
    }
    goal->T_meas_tool = T_meas_frame * target.T_frame_tool;
    if (target.seed.size() != 0) {
      goal->seed = target.seed;
      return true;
    }
    const ConfigurationRules::Solution s = rules_->Solve(*ik_, goal->T_meas_tool, target.configuration, reference);
    if (s.found) {
      goal->seed = s.q;
      return true;
    }
    if (target.configuration.empty()) {
      keep(target, "the controller does not reach the target inside its joint limits");
      return false;
    }
    goal->seed = RealArmSeed(*goal, target.configuration, reference);
    if (goal->seed.size() == 0) {
      keep(target, "the real arm has no solution on the branch its configuration names (nor has the controller)");
      return false;
    }
    return true;
  };
  // A target not reached is sent as written (its seed); a reached one as compensated, its numbers rewritten.
  const auto take = [&](size_t i, const CompensationTarget& goal, const CompensationResult& r) -> Eigen::VectorXd {
    const ProgramTarget& target = targets[i];
    reference = goal.seed;
    if (r.report.status != CompensationStatus::kConverged) {
      keep(target, ToString(r.report.status) + ": " + r.report.message);
      return goal.seed;
    }
    report.branch_changed += r.report.branch_changed;
    report.max_position_error = std::max(report.max_position_error, r.report.position_error);
    report.max_orientation_error = std::max(report.max_orientation_error, r.report.orientation_error);
    std::vector<double> numbers;
    if (target.kind == ProgramTarget::Kind::kPose) {
      const Eigen::VectorXd q_model =
          controller_.coupling.size() ? Eigen::VectorXd(controller_.coupling * r.q_command) : r.q_command;
      const Eigen::Isometry3d T = T_frame_meas * controller_.model().ForwardKinematics(q_model);
      numbers = format.PoseNumbers(
          target, T, target.configuration.empty() ? std::vector<int>() : rules_->Of(r.q_command), r.q_command);
    } else {
      numbers = format.JointNumbers(target, r.q_command);
    }
    if (numbers.size() != target.numbers.size()) throw std::logic_error("filter: the format wrote a wrong count");
    spans.insert(spans.end(), target.numbers.begin(), target.numbers.end());
    values.insert(values.end(), numbers.begin(), numbers.end());
    out.commands.push_back(r.q_command);
    ++report.filtered;
    return r.q_command;
  };
  RunProgram(*compensator_, targets.size(), build, take);
  out.text = ReplaceNumbers(text, spans, values, options_.keep_tolerance);
  return out;
}

}  // namespace kincal
