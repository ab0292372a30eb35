// kincal import ROBOT.urdf --base LINK --tip LINK --out ROBOT.yaml [--convention urdf|mdh|poe|...]:
// the serial chain of a URDF between two links as a kincal robot (robot/urdf_io.h). The robot file
// remembers the URDF, so `kincal convert ROBOT.yaml --to urdf` writes that file back calibrated.
// kincal import KINEMATICS.yaml --out ROBOT.yaml: a UR kinematics YAML (ur_description, ur_calibration;
// robot/ur_kinematics.h), recognised by its `kinematics:` key or a .yaml/.yml name.
#include <iostream>

#include "apps/commands.h"
#include "framework/error.h"
#include "models/conversion.h"
#include "robot/robot_file.h"
#include "robot/ur_kinematics.h"
#include "robot/urdf_io.h"

namespace kincal::app {

void AddImportCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("import", "a URDF chain (urdfdom) or a UR kinematics YAML as a robot file");
  auto path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto options = std::make_shared<UrdfImportOptions>();
  cmd->add_option("file", *path, "URDF file, or UR kinematics YAML (ur_description's `kinematics:` map)")->required();
  cmd->add_option("--base", options->base_link, "URDF: link where the chain starts (the robot's base frame)");
  cmd->add_option("--tip", options->tip_link, "URDF: link where the chain ends (the robot's tool frame)");
  cmd->add_option("--convention", options->convention,
                  "convention of the robot file: urdf (each joint's origin and axis, default), mdh, dh, hayati or poe");
  cmd->add_option("--out", *out, "robot file to write")->required();
  cmd->callback([=]() {
    if (LooksLikeUrKinematics(*path)) {
      Robot robot = ReadUrKinematics(*path);
      if (options->convention != "urdf") {
        try {
          robot = robot.WithModel(ConvertModel(robot.model(), options->convention));
        } catch (const std::invalid_argument& e) {
          ThrowInputError(*path + ": " + e.what());
        }
      }
      WriteRobotFile(robot, *out);
      std::cout << "wrote " << *out << " (6 joints of the UR kinematics from base_link_inertia to tool0, "
                << robot.model().convention() << ")\n";
      return;
    }
    if (options->base_link.empty() || options->tip_link.empty()) {
      ThrowInputError(*path + ": a URDF needs --base and --tip (the links where the chain starts and ends)");
    }
    const Robot robot = ImportUrdf(*path, *options);
    WriteRobotFile(robot, *out);
    std::cout << "wrote " << *out << " (" << robot.dof() << " joints from '" << options->base_link << "' to '"
              << options->tip_link << "', " << robot.model().convention() << ")\n";
  });
}

}  // namespace kincal::app
