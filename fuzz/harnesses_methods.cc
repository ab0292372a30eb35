// Harnesses that need the registered methods: study files, method options, the pipeline
// (fuzz/harnesses.h).
#include "fuzz/harnesses.h"

#include <yaml-cpp/yaml.h>

#include "compensators/compensator.h"
#include "framework/dataset.h"
#include "estimators/estimator.h"
#include "robot/robot_file.h"
#include "studies/study.h"
#include "fuzz/harness_util.h"

namespace kincal::fuzz {

int FuzzStudyFile(const uint8_t* data, size_t size) {
  // Placed among the examples, so that the robot files a study names (../robots/...) are found.
  const std::string source = std::string(KINCAL_SOURCE_DIR) + "/examples/studies/fuzz.yaml";
  Accepts(source, [&] {
    const Study study = ParseStudy(Text(data, size), source);
    const std::vector<DatasetVariant> variants = Variants(study);
    // The plan of a study of a billion trials is a legal, if hopeless, request; its size is the user's
    // choice, not a reader's defect, so only plans of a reasonable size are made here.
    const double items = static_cast<double>(variants.size()) * study.trials * study.pipelines.size();
    if (items <= 1e5) WorkItems(study, variants);
  });
  return 0;
}

int FuzzOptions(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::vector<std::string> methods;
  for (const auto& name : Estimators().RegisteredNames()) methods.push_back("e:" + name);
  for (const auto& name : Compensators().RegisteredNames()) methods.push_back("c:" + name);
  const std::string method = methods[data[0] % methods.size()];
  const std::string source = "options.yaml";
  const std::string text = Text(data + 1, size - 1);
  Accepts(source, [&] {
    YAML::Node node;
    try {
      node = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw std::invalid_argument(source + ": invalid YAML");
    }
    // The command line prefixes option errors with the file's name (apps/cli_util); so does this.
    try {
      if (method[0] == 'e')
        Estimators().Create(method.substr(2), node);
      else
        Compensators().Create(method.substr(2), node);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(source + ": " + e.what());
    }
  });
  return 0;
}

int FuzzPipeline(const uint8_t* data, size_t size) {
  const std::string text = Text(data, size);
  const size_t split = text.find("\n@@\n");
  if (split == std::string::npos) return 0;
  Robot robot;
  Dataset dataset;
  if (!Accepts("robot.yaml", [&] { robot = ParseRobotYaml(text.substr(0, split), "robot.yaml"); })) return 0;
  if (!Accepts("data.csv", [&] {
        dataset = ParseDatasetCsv(text.substr(split + 4), "data.csv");
        dataset.Validate(robot.dof());
      })) {
    return 0;
  }
  // Short: a few rows and iterations, so that each input takes milliseconds.
  if (dataset.rows.size() > 12) dataset.rows.resize(12);
  Robot identified;
  YAML::Node options;
  options["max_iterations"] = 5;
  EstimationReport report;
  Accepts("", [&] { report = Estimators().Create("least_squares", options)->Estimate(robot, dataset, &identified); });
  if (identified.dof() != robot.dof()) return 0;  // refused: nothing to compensate with
  if (report.status == EstimationStatus::kConverged || report.status == EstimationStatus::kIterationLimit) {
    for (const auto& p : report.parameters) ExpectFinite(p.value, "an identified parameter");
  }
  std::unique_ptr<Compensator> compensator = Compensators().Create("jacobian", YAML::Node());
  if (!Accepts("", [&] { compensator->Prepare(robot, identified); })) return 0;
  for (size_t i = 0; i < dataset.rows.size() && i < 2; ++i) {
    CompensationTarget target;
    target.T_meas_tool.translation() = dataset.rows[i].p;
    target.has_orientation = false;
    CompensationResult result;
    if (!Accepts("", [&] { result = compensator->Compensate(target); })) continue;
    for (Eigen::Index j = 0; j < result.q_command.size(); ++j) ExpectFinite(result.q_command[j], "a compensated joint");
  }
  return 0;
}

}  // namespace kincal::fuzz
