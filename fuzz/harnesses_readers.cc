// Harnesses of the file readers that need only the framework (fuzz/harnesses.h).
#include "fuzz/harnesses.h"

#include "compensators/compensation_targets.h"
#include "compensators/compensator.h"
#include "framework/dataset.h"
#include "robot/robot_file.h"
#include "fuzz/harness_util.h"

namespace kincal::fuzz {

int FuzzRobotFile(const uint8_t* data, size_t size) {
  const std::string source = "robot.yaml";
  Robot robot;
  if (!Accepts(source, [&] { robot = ParseRobotYaml(Text(data, size), source); })) return 0;
  // What kincal writes, it reads back: the robot file written from an accepted robot is accepted.
  const std::string written = RobotToYaml(robot);
  try {
    const Robot again = ParseRobotYaml(written, "written.yaml");
    if (again.dof() != robot.dof()) Finding("the written robot has another number of joints");
  } catch (const std::exception& e) {
    Finding(std::string("the written robot file is refused: ") + e.what() + "\n" + written);
  }
  return 0;
}

int FuzzDataset(const uint8_t* data, size_t size) {
  const std::string source = "data.csv";
  Dataset dataset;
  if (!Accepts(source, [&] { dataset = ParseDatasetCsv(Text(data, size), source); })) return 0;
  for (const Measurement& m : dataset.rows) {
    for (int i = 0; i < 3; ++i) ExpectFinite(m.p[i], "an accepted position");
    for (Eigen::Index i = 0; i < m.q.size(); ++i) ExpectFinite(m.q[i], "an accepted joint value");
  }
  const std::string written = DatasetToCsv(dataset);
  try {
    const Dataset again = ParseDatasetCsv(written, "written.csv");
    if (again.rows.size() != dataset.rows.size() || again.dof != dataset.dof) Finding("the written dataset differs");
  } catch (const std::exception& e) {
    Finding(std::string("the written dataset is refused: ") + e.what());
  }
  return 0;
}

int FuzzTargets(const uint8_t* data, size_t size) {
  const std::string source = "targets.csv";
  Accepts(source, [&] {
    const Dataset dataset = ParseDatasetCsv(Text(data, size), source);
    for (const CompensationTarget& t : CompensationTargetsFrom(dataset, 6)) {
      for (int i = 0; i < 3; ++i) ExpectFinite(t.T_meas_tool.translation()[i], "a target position");
    }
  });
  return 0;
}

}  // namespace kincal::fuzz
