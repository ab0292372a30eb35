// kincal compensate --nominal N.yaml --identified I.yaml --targets T.csv --method NAME [--options O.yaml]
//                   --out J.csv
// Targets: x_mm,y_mm,z_mm (or _m), optionally qw,qx,qy,qz (without them: position-only targets) and
// optionally the controller's nominal solution q1_deg..qN_deg (or _rad) as seeds; without seeds the
// nominal inverse kinematics is solved per target (seed_computed = 1).
// Targets are in the measurement frame (the identified robot's), or with --frame base in the robot's base
// frame, the controller's (the frame contract, compensators/compensator.h).
// Output, one row per target in the same order (DESIGN.md "File contracts"): q1..qN in the targets' angle
// unit (the robot file's without seed columns) = the joints to command to a controller that converts
// with the nominal ratios; enc1..encN when the robots have drives; status, iterations, position_error
// (targets' length unit), orientation_error_deg, seed_computed.
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <charconv>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "compensators/compensation_targets.h"
#include "compensators/compensator.h"
#include "compensators/program.h"
#include "framework/dataset.h"
#include "framework/error.h"
#include "robot/robot_file.h"

namespace kincal::app {

namespace {

// What the summary line reports of a program's results.
struct Totals {
  std::map<std::string, int> counts;  // by status
  int branch_changes = 0;
  double max_position = 0.0, max_orientation = 0.0;  // m, rad
};

// The output table (DESIGN.md "File contracts"), with the totals of its rows. Rows are appended to one
// string with std::to_chars: the shortest text that reads back to the same double, without a stream
// (20000 targets write 340000 numbers).
std::string ResultsCsv(const std::vector<CompensationResult>& results, int n, bool drives, const Unit& angle,
                       const Unit& length, Totals* totals) {
  const double deg = M_PI / 180.0;
  std::string out;
  out.reserve(results.size() * (n * 32 + 96));
  const auto append = [&out](auto value) {
    char buffer[32];
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
    (void)ec;
    out.append(buffer, end);
  };
  for (int i = 1; i <= n; ++i) out += "q" + std::to_string(i) + "_" + angle.name + ",";
  if (drives)
    for (int i = 1; i <= n; ++i) out += "enc" + std::to_string(i) + ",";
  out += "status,iterations,position_error_" + length.name + ",orientation_error_deg,seed_computed\n";
  for (const CompensationResult& r : results) {
    for (int i = 0; i < n; ++i) {
      append(r.q_command[i] / angle.to_si);
      out += ',';
    }
    for (int64_t e : r.encoders) {
      append(e);
      out += ',';
    }
    out += ToString(r.report.status);
    out += ',';
    append(r.report.iterations);
    out += ',';
    append(r.report.position_error / length.to_si);
    out += ',';
    append(r.report.orientation_error / deg);
    out += r.report.seed_computed ? ",1\n" : ",0\n";
    ++totals->counts[ToString(r.report.status)];
    totals->branch_changes += r.report.branch_changed;
    totals->max_position = std::max(totals->max_position, r.report.position_error);
    totals->max_orientation = std::max(totals->max_orientation, r.report.orientation_error);
  }
  return out;
}

}  // namespace

void AddCompensateCommand(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("compensate", "joints (and motor counts) that make the identified robot reach targets");
  struct Args {
    std::string nominal, identified, targets, method, options, out, frame = "meas";
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "the controller's robot file (its inverse kinematics and ratios)")
      ->required();
  cmd->add_option("--identified", a->identified, "the identified (real) robot file")->required();
  cmd->add_option("--targets", a->targets, "targets (CSV): x_mm,y_mm,z_mm[,qw,qx,qy,qz][,q1_deg..qN_deg seeds]")
      ->required();
  cmd->add_option("--method", a->method, "compensator (see kincal methods)")->required();
  cmd->add_option("--options", a->options, "the compensator's options (YAML)");
  cmd->add_option("--out", a->out, "joints to write (CSV)")->required();
  cmd->add_option("--frame", a->frame,
                  "frame of the targets: meas (the measurement frame, default) or base (the robot's base frame)")
      ->check(CLI::IsMember({"meas", "base"}));
  cmd->callback([a]() {
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::time_point from, Clock::time_point to) {
      return std::chrono::duration<double>(to - from).count();
    };
    const auto t_start = Clock::now();
    const Robot nominal = ReadRobotFile(a->nominal);
    const Robot identified = ReadRobotFile(a->identified);
    Compensators().Get(a->method);  // an unknown name fails before any work
    const Dataset data = ReadDataset(a->targets);
    std::vector<CompensationTarget> targets = CompensationTargetsFrom(data, nominal.dof());
    if (a->frame == "base") {
      const Robot controller = ControllerRobot(nominal, identified);
      for (CompensationTarget& t : targets) t.T_meas_tool = TargetFromBaseFrame(controller, t.T_meas_tool);
    }
    std::unique_ptr<Compensator> compensator =
        NamingFile(a->options, [&] { return Compensators().Create(a->method, LoadYamlFile(a->options)); });
    const auto t_read = Clock::now();
    NamingFile(a->identified, [&] { compensator->Prepare(nominal, identified); });
    const auto t_prepared = Clock::now();
    // The targets are a program: each is reached from the one before (its commands), unless the file
    // gives the pose the arm comes from (from_q columns). Joint errors of the move depend on it.
    std::vector<CompensationTarget> program = targets;
    for (size_t i = 0; i < program.size(); ++i) {
      if (data.rows[i].from_q) program[i].previous_command = *data.rows[i].from_q;
    }
    const std::vector<CompensationResult> results = CompensateProgram(*compensator, program);
    const auto t_solved = Clock::now();

    const Unit angle = data.dof > 0 ? data.angle_unit : nominal.angle_unit;
    const Unit length = data.length_unit;
    const double deg = M_PI / 180.0;
    Totals totals;
    const std::string out = ResultsCsv(results, nominal.dof(), identified.drives.has_value(), angle, length, &totals);
    WriteFileAtomically(a->out, out);
    const auto t_written = Clock::now();
    std::cout << a->method << ": " << targets.size() << " targets (";
    bool first = true;
    for (const auto& [status, count] : totals.counts) {
      std::cout << (first ? "" : ", ") << count << " " << status;
      first = false;
    }
    if (totals.branch_changes)
      std::cout << "; " << totals.branch_changes << " reached on another branch than the controller's";
    std::cout << "), max position error " << totals.max_position / length.to_si << " " << length.name
              << ", max orientation error " << totals.max_orientation / deg << " deg; wrote " << a->out << "\n"
              << "time: read " << seconds(t_start, t_read) << " s, prepare " << seconds(t_read, t_prepared)
              << " s, solve " << seconds(t_prepared, t_solved) << " s, write " << seconds(t_solved, t_written)
              << " s\n";
  });
}

}  // namespace kincal::app
