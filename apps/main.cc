// kincal: kinematic calibration of serial robot arms. See `kincal --help` and DESIGN.md.
#include <filesystem>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>

#include <yaml-cpp/exceptions.h>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/error.h"
#include "framework/version.h"

int main(int argc, char** argv) {
  CLI::App app{"kincal: kinematic calibration of serial robot arms"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "kincal " KINCAL_VERSION_STRING);
  app.footer(
      "Datasets (CSV, one row per measured marker, in measurement order; '#' lines are comments):\n"
      "  q1_deg..qN_deg (or _rad; _mm/_m for prismatic joints)  commanded joint angles\n"
      "  x_mm,y_mm,z_mm (or _m)  measured position      qw,qx,qy,qz  measured orientation (optional)\n"
      "  optional: enc1..encN (encoder counts), sweep (joint swept, CPA), marker (reflector name),\n"
      "  session (instrument set-up), split (train|test), from_q1_deg..from_qN_deg (the pose before)\n"
      "  other instruments: empty x/y/z cells (a partial point), distance_mm + pivot (a distance),\n"
      "  plane (a contact), point (a socket); fixtures in the robot file (docs/instruments.md)\n"
      "Groups that an estimator's `fixed:` option holds (besides single parameter names):\n"
      "  base, tool, ratios, markers, sessions, joint_<i> (row i of the model), joint_errors,\n"
      "  gravity, harmonic, backlash, approach, or one type on one joint (gravity_2, approach_5)\n"
      "kincal methods --options NAME lists a method's options. Guide: docs/guide/README.md");
  kincal::app::AddFkCommand(app);
  kincal::app::AddSimulateCommand(app);
  kincal::app::AddIdentifyCommand(app);
  kincal::app::AddCheckCommand(app);
  kincal::app::AddConvertCommand(app);
  kincal::app::AddImportCommand(app);
  kincal::app::AddCompensateCommand(app);
  kincal::app::AddPredictCommand(app);
  kincal::app::AddIkCommand(app);
  kincal::app::AddPlanCommand(app);
  kincal::app::AddFilterCommand(app);
  kincal::app::AddMethodsCommand(app);
  kincal::app::AddStudyCommand(app);
  kincal::app::AddMergeCommand(app);
  kincal::app::AddDemoCommand(app);
  // Read before parsing (kincal::app::LoadPlugins): listed here for --help.
  std::vector<std::string> plugins;
  app.add_option("--plugin", plugins,
                 "load estimators and compensators from a plugin library (before or after the subcommand, "
                 "repeatable; also KINCAL_PLUGIN_PATH, colon-separated)");
  try {
    std::vector<char*> args = kincal::app::LoadPlugins(argc, argv);
    app.parse(static_cast<int>(args.size()), args.data());
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "kincal: " << e.what() << " (see kincal --help)\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    // The promise is one line on stderr (docs/RELIABILITY.md): readers escape what they quote; this
    // keeps any other message on one line too.
    std::cerr << "kincal: " << kincal::OneLine(e.what()) << "\n";
    return 2;
  } catch (const YAML::Exception& e) {
    std::cerr << "kincal: " << kincal::OneLine(e.what()) << "\n";
    return 2;
  } catch (const kincal::IoError& e) {
    // An output that cannot be written (a full disk, permissions): the file and the system's reason.
    std::cerr << "kincal: " << e.what() << "\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder that cannot be created or read (permissions, a file in the way, a full disk).
    std::cerr << "kincal: " << e.path1().string() << ": " << e.code().message() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // Input too large for this machine's memory (readers refuse what they can estimate beforehand).
    std::cerr << "kincal: out of memory: the input is too large for the memory available\n";
    return 2;
  } catch (const std::exception& e) {
    // Every reader reports bad input as std::invalid_argument; anything else is a defect of kincal
    // (docs/RELIABILITY.md), reported as such.
    std::cerr << "kincal: internal error (please report): " << e.what() << "\n";
    return 1;
  }
  return 0;
}
