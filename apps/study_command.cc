// kincal study STUDY.yaml --out DIR [--threads N] [--shard i/N]
// Runs a study (studies/study.h describes the file) and writes results, plots and report.md.
// Resumable: finished work items are journaled in DIR; the same command again continues.
// SIGTERM and SIGINT (Slurm preemption, a time limit, Ctrl-C) stop taking new items; the items in flight
// finish and are journaled; the command exits with 128 + the signal's number. A second Ctrl-C ends it at once
// (the journal loses at most the items in flight).
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "apps/commands.h"
#include "studies/progress.h"
#include "studies/runner.h"
#include "studies/study.h"

namespace kincal::app {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void OnStopSignal(int signal) {
  if (signal == SIGINT && g_stop_signal == SIGINT) {  // Ctrl-C twice: now
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
  }
  // A repeated SIGTERM (Slurm signals the batch script and its children alike) changes nothing.
  g_stop_signal = signal;
}

void InstallStopHandlers() {
  struct sigaction action = {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

}  // namespace

void AddStudyCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("study", "run a study: datasets x estimators x compensators x trials -> report");
  struct Args {
    std::string study, out, shard = "1/1";
    int threads = 0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("study", a->study, "study file (YAML)")->required();
  cmd->add_option("--out", a->out,
                  "output folder (created): report.md, results.csv, plots/, ...; its study.journal lets the same "
                  "command continue a stopped run")
      ->required();
  cmd->add_option("--threads", a->threads, "worker threads (default: the study's, else every core)");
  cmd->add_option("--shard", a->shard, "run slice i of N of the work items (combine with kincal merge)");
  cmd->callback([a]() {
    const Study study = ReadStudyFile(a->study);
    StudyRunOptions options;
    ParseShard(a->shard, &options.shard_index, &options.shard_count);
    options.threads = a->threads;
    options.progress = &std::cerr;
    options.interactive = StderrIsTerminal();
    options.stop_requested = []() { return g_stop_signal != 0; };
    InstallStopHandlers();
    const StudyRunSummary s = RunStudy(study, a->out, options);
    if (s.stopped) {
      std::fprintf(stderr,
                   "kincal: stopped by signal %d: %d of %d work items done (%d in this run), kept in %s/study.journal; "
                   "the same command continues\n",
                   static_cast<int>(g_stop_signal), s.items_resumed + s.items_finished, s.items_run, s.items_finished,
                   a->out.c_str());
      std::fflush(stdout);
      std::exit(128 + static_cast<int>(g_stop_signal));
    }
    std::printf("ran %d of %d work items on %d threads in %.1f s", s.items_run, s.items_total, s.threads, s.seconds);
    if (s.items_resumed > 0) std::printf(" (%d from the journal of an earlier run)", s.items_resumed);
    std::printf("\n");
    if (options.shard_count == 1) {
      std::printf("wrote %s/report.md\n", a->out.c_str());
    } else {
      std::printf("wrote shard %s to %s; combine all shards with: kincal merge DIR1 DIR2 ... --out DIR\n",
                  a->shard.c_str(), a->out.c_str());
    }
  });
}

}  // namespace kincal::app
