// kincal convert ROBOT.yaml --to CONVENTION --out OUT : the same robot in another convention, with
// identical forward kinematics (e.g. to poe before calibrating an arm with parallel axes), or as a URDF
// (--to urdf with an .urdf output): a robot imported from a URDF is written as that file with only the
// joint numbers changed (robot/urdf_io.h).
#include <iostream>

#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "robot/robot_file.h"
#include "models/conversion.h"
#include "robot/urdf_io.h"

namespace kincal::app {
namespace {
bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

void AddConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert", "rewrite a robot file in another convention (same kinematics)");
  auto robot_path = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  cmd->add_option("robot", *robot_path, "robot file (YAML)")->required();
  cmd->add_option("--to", *to, "target convention: mdh, dh, hayati, poe or urdf (from any)")->required();
  cmd->add_option("--out", *out, "file to write: a robot file (YAML), or a URDF when --to urdf and it ends in .urdf")
      ->required();
  cmd->callback([=]() {
    const Robot robot = ReadRobotFile(*robot_path);
    // A robot that has no exact form in the convention asked for is refused by the conversion, which
    // knows no file: the message names the robot file (a URDF source names itself).
    auto named = [&](auto&& convert) {
      try {
        return convert();
      } catch (const std::invalid_argument& e) {
        ThrowInputError(*robot_path + ": " + e.what());
      }
    };
    if (*to == "urdf" && (EndsWith(*out, ".urdf") || EndsWith(*out, ".xml"))) {
      WriteFileAtomically(*out, robot.urdf ? RobotToUrdf(robot) : named([&] { return RobotToUrdf(robot); }));
      std::cout << "wrote " << *out << " (URDF"
                << (robot.urdf ? ", edited from " + robot.urdf->path + "; the base is not part of it" : "") << ")\n";
      return;
    }
    const Robot result = robot.WithModel(named([&] { return ConvertModel(robot.model(), *to); }));
    WriteRobotFile(result, *out);
    std::cout << "wrote " << *out << " (" << *to << ")\n";
  });
}

}  // namespace kincal::app
