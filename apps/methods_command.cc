// kincal methods : every model, estimator and compensator; with --options NAME, the options of the
// estimator or compensator NAME, or of the tool ik or filter (key, type, default, doc), from the
// declaration its options are read by.
#include <algorithm>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "doctor/doctor.h"
#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "framework/error.h"
#include "models/model_factory.h"
#include "planning/plan_options.h"
#include "programs/filter.h"
#include "robot/nominal_ik.h"

namespace kincal::app {

namespace {

void Pad(const std::string& text, size_t width) {
  std::cout << text;
  for (size_t i = text.size(); i < width; ++i) std::cout << ' ';
}

template <typename R>
void List(const char* title, const R& registry) {
  std::cout << title << ":\n";
  for (const auto& name : registry.RegisteredNames()) {
    std::cout << "  ";
    Pad(name, 20);
    std::cout << registry.Get(name).description << "\n";
  }
}

// One line per option: key, type, default, doc, in aligned columns.
void PrintDocs(const std::vector<OptionDoc>& docs) {
  if (docs.empty()) std::cout << "  (no options)\n";
  size_t key_width = 0, type_width = 0, default_width = 0;
  for (const OptionDoc& o : docs) {
    key_width = std::max(key_width, o.key.size());
    type_width = std::max(type_width, o.type.size());
    default_width = std::max(default_width, o.default_value.size());
  }
  for (const OptionDoc& o : docs) {
    std::cout << "  ";
    Pad(o.key, key_width + 2);
    Pad(o.type, type_width + 2);
    Pad(o.default_value, default_width + 2);
    std::cout << o.doc << "\n";
  }
}

template <typename R>
bool PrintOptions(const char* kind, const R& registry, const std::string& name) {
  if (!registry.IsRegistered(name)) return false;
  const auto& entry = registry.Get(name);
  std::cout << kind << " " << name << ": " << entry.description << "\n";
  PrintDocs(entry.options);
  return true;
}

// The options of the tools that are not registered methods: `ik` (kincal ik --options, with its
// numeric solver's map), `filter` (kincal filter --filter-options) and `check` (kincal check --options).
bool PrintToolOptions(const std::string& name) {
  if (name == "ik") {
    std::cout << "inverse kinematics (kincal ik --options):\n";
    PrintDocs(NominalIkOptions::Table().Docs());
    std::cout << "numeric: the numeric solver's map:\n";
    PrintDocs(InverseKinematicsOptions::Table().Docs());
    return true;
  }
  if (name == "filter") {
    std::cout << "filter (kincal filter --filter-options):\n";
    PrintDocs(FilterOptions::Table().Docs());
    return true;
  }
  if (name == "plan") {
    std::cout << "plan (kincal plan --plan-options):\n";
    PrintDocs(PlanOptions::Table().Docs());
    return true;
  }
  if (name == "check") {
    std::cout << "check (kincal check --options):\n";
    PrintDocs(doctor::DoctorOptions::Table().Docs());
    return true;
  }
  return false;
}

}  // namespace

void AddMethodsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("methods", "list every model, estimator and compensator");
  auto options = std::make_shared<std::string>();
  cmd->add_option("--options", *options,
                  "print the options of this estimator or compensator (or of the tools ik, filter and plan): key, type, "
                  "default, what it does");
  cmd->callback([options]() {
    if (!options->empty()) {
      const bool estimator = PrintOptions("estimator", Estimators(), *options);
      if (estimator && Compensators().IsRegistered(*options)) std::cout << "\n";
      const bool compensator = PrintOptions("compensator", Compensators(), *options);
      if (!estimator && !compensator && !PrintToolOptions(*options)) {
        std::string list;
        for (const auto& n : Estimators().RegisteredNames()) list += (list.empty() ? "" : ", ") + n;
        for (const auto& n : Compensators().RegisteredNames()) list += ", " + n;
        ThrowInputError("--options: no estimator, compensator or tool '" + *options + "' (registered: " + list +
                        "; tools: ik, filter)");
      }
      return;
    }
    List("models (robot file `convention`, kincal convert --to)", Models());
    List("estimators (kincal identify --method; options: kincal methods --options NAME)", Estimators());
    List("compensators (kincal compensate --method; options: kincal methods --options NAME)", Compensators());
    List("program formats (kincal filter --format)", ProgramFormats());
  });
}

}  // namespace kincal::app
