// kincal check --nominal N.yaml --data D.csv [--report CHECK.json] [--options O.yaml]
// The calibration doctor (doctor/doctor.h): what is wrong with the data or the set-up, by cause, with the
// evidence and the repair. Exit 0 when the data were read (findings or none), 2 when they could not be.
#include <iostream>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "doctor/doctor.h"
#include "framework/atomic_file.h"
#include "robot/robot_file.h"

namespace kincal::app {

void AddCheckCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("check", "find what is wrong with a dataset and its set-up (units, joint columns, "
                                          "zeros, tool, outliers, a moved instrument, joints that never moved)");
  struct Args {
    std::string nominal, data, report, options;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "nominal robot file (the controller's model)")->required();
  cmd->add_option("--data", a->data, "dataset (CSV)")->required();
  cmd->add_option("--report", a->report, "JSON report of the findings");
  cmd->add_option("--options", a->options, "the doctor's margins (YAML; kincal methods --options check)");
  cmd->callback([a]() {
    const doctor::DoctorOptions options =
        NamingFile(a->options, [&] { return doctor::DoctorOptions::Table().Read(LoadYamlFile(a->options)); });
    const Robot nominal = ReadRobotFile(a->nominal);
    const Dataset data = ReadDataset(a->data);
    data.Validate(nominal.dof());
    const std::vector<doctor::Finding> findings =
        NamingFile(a->data, [&] { return doctor::Diagnose(nominal, data, options); });
    for (const auto& f : findings) std::cout << doctor::FindingLine(f) << "\n";
    std::cout << "check: " << findings.size() << (findings.size() == 1 ? " finding" : " findings") << " on "
              << data.rows.size() << " rows of " << a->data << "\n";
    if (!a->report.empty()) {
      const double rms = doctor::RmsAsGiven(nominal, data, options);
      WriteFileAtomically(a->report, doctor::FindingsToJson(findings, rms).dump(2) + "\n");
    }
  });
}

}  // namespace kincal::app
