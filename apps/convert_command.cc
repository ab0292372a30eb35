// kincal convert ROBOT.yaml --to CONVENTION --out OUT.yaml : the same robot in another convention, with
// identical forward kinematics (e.g. to poe before calibrating an arm with parallel axes).
#include <iostream>

#include "apps/commands.h"
#include "framework/robot_file.h"
#include "models/conversion.h"

namespace kincal::app {

void AddConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert", "rewrite a robot file in another convention (same kinematics)");
  auto robot_path = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  cmd->add_option("robot", *robot_path, "robot file (YAML)")->required();
  cmd->add_option("--to", *to, "target convention: poe (from any), hayati (from mdh)")->required();
  cmd->add_option("--out", *out, "robot file to write")->required();
  cmd->callback([=]() {
    const Robot robot = ReadRobotFile(*robot_path);
    const Robot result = robot.WithModel(ConvertModel(robot.model(), *to));
    WriteRobotFile(result, *out);
    std::cout << "wrote " << *out << " (" << *to << ")\n";
  });
}

}  // namespace kincal::app
