// kincal demo [--out DIR]: the seed's experiment in simulation (studies/demo.h), then a summary
// beside the seed's published numbers.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "studies/demo.h"
#include "studies/progress.h"
#include "studies/runner.h"

namespace kincal::app {

void AddDemoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("demo", "the seed's experiment in simulation, with every registered method");
  struct Args {
    std::string out = "kincal-demo";
    DemoOptions demo;
    int threads = 0;
    bool no_iso = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--out", a->out, "output folder (default ./kincal-demo)");
  cmd->add_option("--trials", a->demo.trials, "Monte Carlo trials (default 3)");
  cmd->add_option("--targets", a->demo.extra_targets, "random targets besides the seed's 10 (default 1000)");
  cmd->add_option("--stops", a->demo.stops,
                  "sweep stops per joint; the random dataset has 6 x stops poses (default 20)");
  cmd->add_option("--seed", a->demo.seed, "random seed (default 1)");
  cmd->add_option("--threads", a->threads, "worker threads (default: every core)");
  cmd->add_flag("--no-iso", a->no_iso, "leave out the ISO 9283 cube");
  cmd->callback([a]() {
    const auto t0 = std::chrono::steady_clock::now();
    a->demo.iso = !a->no_iso;
    const std::string text = DemoStudyYaml(a->demo);
    std::filesystem::create_directories(a->out);
    const std::string study_path = a->out + "/study.yaml";
    WriteFileAtomically(study_path, text);
    const Study study = ParseStudy(text, study_path);
    StudyRunOptions options;
    options.threads = a->threads;
    options.progress = &std::cerr;
    options.interactive = StderrIsTerminal();
    options.journal = false;  // a demo rerun with other options overwrites; `kincal study` resumes
    RunStudy(study, a->out, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << DemoSummary(a->out);
    std::printf("demo finished in %.1f s\n", seconds);
  });
}

}  // namespace kincal::app
