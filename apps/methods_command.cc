// kincal methods : every model, estimator and compensator, with availability.
#include <iostream>

#include "apps/commands.h"
#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "models/model_factory.h"

namespace kincal::app {

namespace {
template <typename R>
void List(const char* title, const R& registry) {
  std::cout << title << ":\n";
  for (const auto& name : registry.RegisteredNames()) {
    const auto& entry = registry.Get(name);
    std::cout << "  " << name;
    for (size_t i = name.size(); i < 22; ++i) std::cout << ' ';
    std::cout << entry.description;
    if (!entry.available) std::cout << " [unavailable: " << entry.why_unavailable << "]";
    std::cout << "\n";
  }
}
}  // namespace

void AddMethodsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("methods", "list every model, estimator and compensator");
  cmd->callback([]() {
    std::cout << "models (robot file `convention`):\n";
    for (const auto& c : ModelConventions()) std::cout << "  " << c << "\n";
    List("estimators (kincal identify --method)", Estimators());
    List("compensators (kincal compensate --method)", Compensators());
  });
}

}  // namespace kincal::app
