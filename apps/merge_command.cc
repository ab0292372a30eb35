// kincal merge DIR1 DIR2 ... --out DIR
// Combines the folders of `kincal study --shard i/N` into the folder an unsharded run writes.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "framework/error.h"
#include "studies/report.h"
#include "studies/results_files.h"

namespace kincal::app {

void AddMergeCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("merge", "combine the shard folders of a study into one report");
  struct Args {
    std::vector<std::string> dirs;
    std::string out;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("dirs", a->dirs, "the shards' output folders")->required();
  cmd->add_option("--out", a->out, "output folder (created)")->required();
  cmd->callback([a]() {
    // The shards' files are kincal's own, but they may have been edited, truncated or mixed up since:
    // what the readers do not check field by field is reported as damage here, naming the folders.
    try {
      MergeShards(a->dirs, a->out);
      WriteReport(a->out);
    } catch (const nlohmann::json::exception& e) {
      std::string dirs;
      for (const auto& d : a->dirs) dirs += (dirs.empty() ? "" : ", ") + d;
      ThrowInputError("merge: a study.json in " + dirs + " is damaged (" + e.what() + ")");
    }
    std::printf("merged %zu shards; wrote %s/report.md\n", a->dirs.size(), a->out.c_str());
  });
}

}  // namespace kincal::app
