// kincal fk ROBOT.yaml --q=Q1,...,Qn : the tool pose in the measurement frame, robot file's units.
#include <iostream>

#include <nlohmann/json.hpp>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/error.h"
#include "robot/robot_file.h"

namespace kincal::app {

void AddFkCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("fk", "print T_meas_tool for actual joint angles, as JSON {\"T\": 4x4}");
  auto robot_path = std::make_shared<std::string>();
  auto q_text = std::make_shared<std::string>();
  cmd->add_option("robot", *robot_path, "robot file (YAML)")->required();
  cmd->add_option("--q", *q_text, "joint angles, comma separated, in the robot file's angle unit")->required();
  cmd->callback([=]() {
    const Robot robot = ReadRobotFile(*robot_path);
    const KinematicModel& model = robot.model();
    const std::vector<std::string> items = SplitComma(*q_text);
    if (static_cast<int>(items.size()) != robot.dof()) {
      ThrowInputError("--q: expected " + std::to_string(robot.dof()) + " joint values for " + *robot_path + ", got " +
                      std::to_string(items.size()));
    }
    Eigen::VectorXd q(robot.dof());
    for (int i = 0; i < robot.dof(); ++i) {
      const Unit& u = model.joint_type(i) == JointType::kRevolute ? robot.angle_unit : robot.length_unit;
      q[i] = ParseList(items[i], u, "--q")[0];
    }
    const Eigen::Isometry3d T = model.ForwardKinematics(q);
    if (!T.matrix().allFinite()) {
      ThrowInputError(*robot_path, 0, 0, "the pose is not finite: values out of range in the robot file or --q");
    }
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) {
      nlohmann::json row = nlohmann::json::array();
      for (int c = 0; c < 4; ++c) {
        const double v = T.matrix()(r, c);
        row.push_back(c == 3 && r < 3 ? v / robot.length_unit.to_si : v);
      }
      rows.push_back(row);
    }
    std::cout << nlohmann::json{{"T", rows}, {"units", {{"length", robot.length_unit.name}}}}.dump() << "\n";
  });
}

}  // namespace kincal::app
