// kincal: kinematic calibration of serial robot arms. See `kincal --help` and DESIGN.md.
#include <iostream>
#include <stdexcept>

#include <yaml-cpp/exceptions.h>

#include "apps/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"kincal: kinematic calibration of serial robot arms"};
  app.require_subcommand(1);
  kincal::app::AddFkCommand(app);
  kincal::app::AddSimulateCommand(app);
  kincal::app::AddIdentifyCommand(app);
  kincal::app::AddConvertCommand(app);
  kincal::app::AddImportCommand(app);
  kincal::app::AddCompensateCommand(app);
  kincal::app::AddPredictCommand(app);
  kincal::app::AddIkCommand(app);
  kincal::app::AddMethodsCommand(app);
  kincal::app::AddStudyCommand(app);
  kincal::app::AddMergeCommand(app);
  kincal::app::AddDemoCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "kincal: " << e.what() << " (see kincal --help)\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "kincal: " << e.what() << "\n";
    return 2;
  } catch (const YAML::Exception& e) {
    std::cerr << "kincal: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "kincal: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
