// kincal import ROBOT.urdf --base LINK --tip LINK --out ROBOT.yaml [--convention urdf|mdh|poe|...]:
// the serial chain of a URDF between two links as a kincal robot (robot/urdf_io.h). The robot file
// remembers the URDF, so `kincal convert ROBOT.yaml --to urdf` writes that file back calibrated.
#include <iostream>

#include "apps/commands.h"
#include "robot/robot_file.h"
#include "robot/urdf_io.h"

namespace kincal::app {

void AddImportCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("import", "a URDF chain (urdfdom) as a robot file");
  auto urdf_path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto options = std::make_shared<UrdfImportOptions>();
  cmd->add_option("urdf", *urdf_path, "URDF file")->required();
  cmd->add_option("--base", options->base_link, "link where the chain starts (the robot's base frame)")->required();
  cmd->add_option("--tip", options->tip_link, "link where the chain ends (the robot's tool frame)")->required();
  cmd->add_option("--convention", options->convention,
                  "convention of the robot file: urdf (each joint's origin and axis, default), mdh, dh, hayati or poe");
  cmd->add_option("--out", *out, "robot file to write")->required();
  cmd->callback([=]() {
    const Robot robot = ImportUrdf(*urdf_path, *options);
    WriteRobotFile(robot, *out);
    std::cout << "wrote " << *out << " (" << robot.dof() << " joints from '" << options->base_link << "' to '"
              << options->tip_link << "', " << robot.model().convention() << ")\n";
  });
}

}  // namespace kincal::app
