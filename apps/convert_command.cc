// kincal convert ROBOT.yaml --to CONVENTION --out OUT : the same robot in another convention, with
// identical forward kinematics (e.g. to poe before calibrating an arm with parallel axes), or as a URDF
// (--to urdf with an .urdf output): a robot imported from a URDF is written as that file with only the
// joint numbers changed (robot/urdf_io.h), or as a UR kinematics YAML (--to ur-kinematics,
// robot/ur_kinematics.h): what that file does not hold is listed on stderr and in the file, and with
// --data the held-out RMS error with and without it.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/dataset.h"
#include "models/conversion.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "robot/ur_kinematics.h"
#include "robot/urdf_io.h"

namespace kincal::app {
namespace {
bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
// Writes the UR kinematics file; reports what it does not hold and, given held-out data, its effect.
void WriteUrKinematics(const Robot& robot, const std::string& robot_path, const std::string& out,
                       const std::string& data_path) {
  UrKinematicsExport result;
  try {
    result = ExportUrKinematics(robot, robot_path);
  } catch (const std::invalid_argument& e) {
    ThrowInputError(robot_path + ": " + e.what());
  }
  WriteFileAtomically(out, result.text);
  for (const auto& line : result.dropped) std::cerr << robot_path << ": " << line << "\n";
  std::cout << "wrote " << out << " (UR kinematics, " << result.dropped.size() << " item(s) not held)\n";
  if (data_path.empty()) {
    if (!result.dropped.empty()) {
      std::cout << "their effect on the error: the same command with --data HELD_OUT.csv (rows not used to identify)\n";
    }
    return;
  }
  const Dataset data = ReadDataset(data_path);
  data.Validate(robot.dof());
  // A dataset with a split is scored on its test rows (the others still give each row its previous pose).
  const bool split = data.HasSplit();
  const auto rms = [&](const Robot& model) {
    const std::vector<double> errors = EvaluatePredictions(robot, model, data).position;
    double sum2 = 0.0;
    size_t count = 0;
    for (size_t i = 0; i < errors.size(); ++i) {
      if (split && data.rows[i].split != Split::kTest) continue;
      sum2 += errors[i] * errors[i];
      ++count;
    }
    return std::make_pair(count ? std::sqrt(sum2 / count) : 0.0, count);
  };
  const auto [with, rows] = rms(robot);
  const double held = rms(result.held).first;
  std::printf("%s, %zu %s: RMS position error %.6g mm with the whole robot file, %.6g mm as the UR file holds it "
              "(base and tool set in the controller; drives, coupling and joint errors dropped)\n",
              data_path.c_str(), rows, split ? "test rows" : "rows", with * 1e3, held * 1e3);
}

}  // namespace

void AddConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert", "rewrite a robot file in another convention (same kinematics)");
  auto robot_path = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto data = std::make_shared<std::string>();
  cmd->add_option("robot", *robot_path, "robot file (YAML)")->required();
  cmd->add_option("--to", *to, "target convention: mdh, dh, hayati, poe or urdf (from any), or ur-kinematics (a UR "
                  "kinematics YAML, from any 6R robot)")
      ->required();
  cmd->add_option("--out", *out, "file to write: a robot file (YAML), or a URDF when --to urdf and it ends in .urdf")
      ->required();
  cmd->add_option("--data", *data,
                  "with --to ur-kinematics: held-out dataset on which to measure what the file does not hold (RMS "
                  "with and without)");
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
    if (*to == "ur-kinematics") {
      WriteUrKinematics(robot, *robot_path, *out, *data);
      return;
    }
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
