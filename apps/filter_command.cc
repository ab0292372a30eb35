// kincal filter --nominal N.yaml --identified I.yaml --program IN --out OUT [--format F] [--method M]
//               [--options O.yaml] [--filter-options F.yaml] [--work-object "x y z a b c"] [--tool "x y z a b c"]
// A robot program with its Cartesian targets replaced by filtered ones and its joint targets by
// compensated joints, everything else byte for byte (programs/filter.h). Formats by extension or
// --format: rapid (.mod .prg .modx), krl (.dat), urscript (.script), csv (compensate's targets).
// Targets are in the robot's base frame (the controller's, frame contract of compensators/compensator.h),
// or in the work object --work-object gives (its pose in the base frame: x y z in mm, then A B C in deg,
// R = Rz(A) Ry(B) Rx(C)), for the identified robot file's tool unless --tool gives another (flange to
// tool, same units). --filter-options gives the same as a file (work_object, tool, keep_tolerance; the
// flags win). Targets that are not reached stay as written and are listed (file:line).
#include <chrono>
#include <iostream>
#include <sstream>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "compensators/compensator.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "programs/filter.h"
#include "robot/robot_file.h"

namespace kincal::app {
namespace {

// "x y z a b c" (mm, deg; commas allowed) as a pose: the options table's conversion (programs/filter.h).
Eigen::Isometry3d ParsePose(const std::string& option, const std::string& text) {
  std::string s = text;
  for (char& c : s) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(s);
  std::vector<double> v;
  double x = 0.0;
  while (in >> x) v.push_back(x);
  std::string rest;
  in.clear();
  try {
    if (in >> rest) throw std::invalid_argument("not a number");
    return PoseFromXyzAbc(v);
  } catch (const std::invalid_argument&) {
    ThrowInputError(option + ": expected 6 numbers \"x y z a b c\" (mm, deg), got '" + text + "'");
  }
}

}  // namespace

void AddFilterCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("filter", "a robot program with its targets compensated for the identified robot");
  struct Args {
    std::string nominal, identified, program, out, format, method = "analytic_derivative", options, filter_options,
                                                           work_object, tool;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "the controller's robot file")->required();
  cmd->add_option("--identified", a->identified, "the identified (real) robot file")->required();
  cmd->add_option("--program", a->program, "the robot program to filter")->required();
  cmd->add_option("--out", a->out, "the filtered program to write")->required();
  cmd->add_option("--format", a->format, "a program format `kincal methods` lists (default: by the program's extension)");
  cmd->add_option("--method", a->method, "compensator (default analytic_derivative; see kincal methods)");
  cmd->add_option("--options", a->options, "the compensator's options (YAML)");
  cmd->add_option("--filter-options", a->filter_options,
                  "the filter's options (YAML): work_object, tool, keep_tolerance (kincal methods --options filter)");
  cmd->add_option("--work-object", a->work_object,
                  "the targets' frame in the robot's base frame: \"x y z a b c\" (mm, deg; R = Rz(a) Ry(b) Rx(c))");
  cmd->add_option("--tool", a->tool, "the targets' tool, flange to tool: \"x y z a b c\" (mm, deg)");
  cmd->callback([a]() {
    const auto t0 = std::chrono::steady_clock::now();
    const Robot nominal = ReadRobotFile(a->nominal);
    const Robot identified = ReadRobotFile(a->identified);
    const std::unique_ptr<ProgramFormat> format =
        MakeProgramFormat(a->format.empty() ? ProgramFormatFromExtension(a->program) : a->format);
    FilterOptions options =
        NamingFile(a->filter_options, [&] { return FilterOptions::Table().Read(LoadYamlFile(a->filter_options)); });
    if (!a->work_object.empty()) options.T_base_frame = ParsePose("--work-object", a->work_object);
    if (!a->tool.empty()) options.T_flange_tool = ParsePose("--tool", a->tool);
    Compensators().Get(a->method);
    std::unique_ptr<Compensator> compensator =
        NamingFile(a->options, [&] { return Compensators().Create(a->method, LoadYamlFile(a->options)); });
    const std::string text = ReadFileToString(a->program);
    const ProgramFilter filter = NamingFile(a->identified, [&] {
      return ProgramFilter(nominal, identified, std::move(compensator), options, format->convention());
    });
    const FilteredProgram result = filter.Filter(*format, text, a->program);
    WriteFileAtomically(a->out, result.text);
    const FilterReport& r = result.report;
    for (const std::string& line : r.not_reached) std::cerr << "not filtered: " << line << "\n";
    std::cout << format->name() << ": " << r.pose_targets << " Cartesian and " << r.joint_targets << " joint targets; "
              << r.filtered << " filtered, " << r.not_reached.size() << " kept as written";
    if (r.branch_changed) std::cout << ", " << r.branch_changed << " on another branch than the one named";
    std::cout << "; max error of the identified arm " << r.max_position_error * 1e3 << " mm, "
              << r.max_orientation_error * 180 / M_PI << " deg; wrote " << a->out << " ("
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s)\n";
  });
}

}  // namespace kincal::app
