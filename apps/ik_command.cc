// kincal ik ROBOT.yaml --targets T.csv --out Q.csv [--all-branches] [--options O.yaml]
// Inverse kinematics of a robot (robot/nominal_ik.h): closed form where the geometry allows, numeric
// otherwise. Targets: x_mm,y_mm,z_mm (or _m) with qw,qx,qy,qz (without them: position-only, numeric),
// optionally q1_deg..qN_deg (or _rad) as each row's reference joints. The targets are a program: each is
// solved on the branch closest to the previous row's solution (the first: to the middle of the limits),
// unless the row gives its reference.
// Output, one row per target in order: q1..qN (the model's joint angles, the robot file's angle unit),
// status (solved, out_of_limits, unreachable, singular), branch (closed-form branch, -1 numeric),
// position_error (targets' length unit), orientation_error_deg. --all-branches: every closed-form branch,
// one row each, with a leading `target` column (1-based); a target without any gets one numeric row.
#include <charconv>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "framework/dataset.h"
#include "framework/error.h"
#include "robot/nominal_ik.h"
#include "robot/robot_file.h"

namespace kincal::app {

namespace {

// The solver's options from the file at `path` (none: the defaults), for a robot of n joints; bad values
// are input errors with their line and column.
NominalIkOptions ReadIkOptions(const std::string& path, int n) {
  const YAML::Node options_file = LoadYamlFile(path);
  const NominalIkOptions options = NamingFile(path, [&] { return NominalIkOptions::Table().Read(options_file); });
  if (!options.configuration.empty() && static_cast<int>(options.configuration.size()) != n) {
    // As the options reader words its errors (framework/options.h).
    const YAML::Mark mark = options_file["configuration"].Mark();
    ThrowInputError(
        path + ": line " + std::to_string(mark.line + 1) + ", column " + std::to_string(mark.column + 1) +
        ": options of inverse kinematics: 'configuration': " + std::to_string(options.configuration.size()) +
        " signs for a robot of " + std::to_string(n) + " joints (one per joint)");
  }
  return options;
}

// The targets file for a robot of n joints: points with optional orientations and reference joints.
Dataset ReadIkTargets(const std::string& path, int n) {
  Dataset data = ReadDataset(path);
  data.RequireFullPoints("kincal ik (targets)");
  if (data.dof != 0 && data.dof != n) {
    ThrowInputError(data.source, data.header_line, 0,
                    "the targets have " + std::to_string(data.dof) + " joint (reference) columns but the robot has " +
                        std::to_string(n) + " joints");
  }
  if (data.HasEncoders() || data.HasSweeps() || data.HasMarkers() || data.HasSessions() || data.HasSplit() ||
      data.HasFromColumns()) {
    ThrowInputError(data.source, data.header_line, 0,
                    "targets take x, y, z, optionally qw, qx, qy, qz and references q1..qN; enc, sweep, marker, "
                    "session, split and from_q columns have no meaning here");
  }
  if (data.rows.empty()) ThrowInputError(data.source, data.header_line, 0, "no targets");
  return data;
}

// The shortest decimal text that reads back as `value`, appended to *out.
template <typename T>
void AppendNumber(T value, std::string* out) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  (void)ec;
  out->append(buffer, end);
}

// "3 solved, 1 unreachable": the count of each status.
std::string CountsInWords(const std::map<std::string, int>& counts) {
  std::string words;
  for (const auto& [status, count] : counts) words += (words.empty() ? "" : ", ") + std::to_string(count) + " " + status;
  return words;
}

}  // namespace

void AddIkCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "ik", "joint solutions of a robot for target poses (every branch in closed form where possible)");
  struct Args {
    std::string robot, targets, out, options;
    bool all_branches = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("robot", a->robot, "robot file (YAML)")->required();
  cmd->add_option("--targets", a->targets, "targets (CSV): x_mm,y_mm,z_mm[,qw,qx,qy,qz][,q1_deg..qN_deg references]")
      ->required();
  cmd->add_option("--out", a->out, "joint solutions to write (CSV)")->required();
  cmd->add_flag("--all-branches", a->all_branches, "every closed-form branch of each target, one row each");
  cmd->add_option("--options", a->options, "the solver's options (YAML; kincal methods --options ik)");
  cmd->callback([a]() {
    const Robot robot = ReadRobotFile(a->robot);
    const int n = robot.dof();
    const Dataset data = ReadIkTargets(a->targets, n);
    const NominalIkOptions options = ReadIkOptions(a->options, n);
    const NominalInverseKinematics ik =
        NamingFile(a->options, [&] { return NominalInverseKinematics(robot, options); });
    const Unit angle = robot.angle_unit;
    const Unit length = data.length_unit;
    const double deg = M_PI / 180.0;
    std::string out;
    const auto append = [&out](auto value) { AppendNumber(value, &out); };
    if (a->all_branches) out += "target,";
    for (int i = 1; i <= n; ++i) out += "q" + std::to_string(i) + "_" + angle.name + ",";
    out += "status,branch,position_error_" + length.name + ",orientation_error_deg\n";
    const auto write = [&](size_t row, const IkSolution& s) {
      if (a->all_branches) {
        append(row + 1);
        out += ',';
      }
      for (int j = 0; j < n; ++j) {
        append(s.q[j] / angle.to_si);
        out += ',';
      }
      out += ToString(s.status);
      out += ',';
      append(s.branch);
      out += ',';
      append(s.position_error / length.to_si);
      out += ',';
      append(s.orientation_error / deg);
      out += '\n';
    };
    std::map<std::string, int> counts;
    Eigen::VectorXd previous;
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < data.rows.size(); ++i) {
      const Measurement& m = data.rows[i];
      const Eigen::VectorXd reference = data.dof > 0 ? m.q : previous;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = m.p;
      IkSolution s;
      if (!m.orientation) {
        s = ik.SolvePosition(m.p, reference);
      } else {
        T.linear() = m.orientation->toRotationMatrix();
        s = ik.Solve(T, reference);
      }
      ++counts[ToString(s.status)];
      previous = s.q;
      if (a->all_branches && m.orientation) {
        const std::vector<IkSolution> all = ik.AllBranches(T, reference);
        for (const IkSolution& b : all) write(i, b);
        if (all.empty()) write(i, s);
      } else {
        write(i, s);
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    WriteFileAtomically(a->out, out);
    std::cout << "ik (" << ik.method() << "): " << data.rows.size() << " targets (" << CountsInWords(counts) << "), "
              << seconds / data.rows.size() * 1e6 << " us per target; wrote " << a->out << "\n";
  });
}

}  // namespace kincal::app
