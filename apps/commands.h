#pragma once
// Each `kincal` subcommand lives in its own file and registers itself on the app here. A command's
// callback throws std::invalid_argument for bad input; main() turns that into one line on stderr and
// exit status 2.
#include <CLI/CLI.hpp>

namespace kincal::app {

void AddFkCommand(CLI::App& app);
void AddSimulateCommand(CLI::App& app);
void AddMethodsCommand(CLI::App& app);
void AddIdentifyCommand(CLI::App& app);
void AddConvertCommand(CLI::App& app);
void AddCompensateCommand(CLI::App& app);
void AddStudyCommand(CLI::App& app);
void AddMergeCommand(CLI::App& app);
void AddDemoCommand(CLI::App& app);
void AddPredictCommand(CLI::App& app);
void AddImportCommand(CLI::App& app);
void AddIkCommand(CLI::App& app);
void AddFilterCommand(CLI::App& app);
void AddPlanCommand(CLI::App& app);
void AddCheckCommand(CLI::App& app);

}  // namespace kincal::app
