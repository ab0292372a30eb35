// kincal study STUDY.yaml --out DIR [--threads N] [--shard i/N]
// Runs a study (framework/study/study.h describes the file) and writes results, plots and report.md.
#include <cstdio>
#include <iostream>

#include "apps/commands.h"
#include "framework/study/progress.h"
#include "framework/study/runner.h"
#include "framework/study/study.h"

namespace kincal::app {

void AddStudyCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("study", "run a study: datasets x estimators x compensators x trials -> report");
  struct Args {
    std::string study, out, shard = "1/1";
    int threads = 0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("study", a->study, "study file (YAML)")->required();
  cmd->add_option("--out", a->out, "output folder (created): report.md, results.csv, plots/, ...")->required();
  cmd->add_option("--threads", a->threads, "worker threads (default: the study's, else every core)");
  cmd->add_option("--shard", a->shard, "run slice i of N of the work items (combine with kincal merge)");
  cmd->callback([a]() {
    const Study study = ReadStudyFile(a->study);
    StudyRunOptions options;
    ParseShard(a->shard, &options.shard_index, &options.shard_count);
    options.threads = a->threads;
    options.progress = &std::cerr;
    options.interactive = StderrIsTerminal();
    const StudyRunSummary s = RunStudy(study, a->out, options);
    std::printf("ran %d of %d work items on %d threads in %.1f s\n", s.items_run, s.items_total, s.threads, s.seconds);
    if (options.shard_count == 1) {
      std::printf("wrote %s/report.md\n", a->out.c_str());
    } else {
      std::printf("wrote shard %s to %s; combine all shards with: kincal merge DIR1 DIR2 ... --out DIR\n",
                  a->shard.c_str(), a->out.c_str());
    }
  });
}

}  // namespace kincal::app
