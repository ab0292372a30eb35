#pragma once
// Runs a study: every work item (or one shard's share of them) on a pool of threads, then writes the
// result files and, for a whole study, the report. Each item is seeded from (study seed, dataset,
// variant, trial) alone, so the results do not depend on the number of threads or on scheduling.
#include <functional>
#include <ostream>
#include <string>

#include "studies/study.h"

namespace kincal {

struct StudyRunOptions {
  int threads = 0;      // 0: the study's `threads`, else every core
  int shard_index = 1;  // 1-based; items with index % shard_count == shard_index - 1 run
  int shard_count = 1;
  std::ostream* progress = nullptr;  // null: silent
  bool interactive = false;          // progress as a bar redrawn in place (stderr is a terminal)
  bool write_report = true;          // whole studies only; shards are reported by `kincal merge`
  // Resumable runs (studies/journal.h): every finished item is recorded in
  // out_dir/study.journal; a run on a folder with a journal of the same study and shard runs only the
  // items it lacks. A journal of another study is refused. false: no journal is read or written.
  bool journal = true;
  // Polled before each work item (from any worker thread; must be thread-safe). Once it returns true no
  // new item starts; the items in flight finish and are journaled; RunStudy returns with `stopped` set
  // and writes no result file. Empty: never stops.
  std::function<bool()> stop_requested;
  bool IsValid(std::string* why) const;
};

struct StudyRunSummary {
  int items_total = 0;
  int items_run = 0;                 // this shard's items, including those taken from the journal
  int items_resumed = 0;             // taken from the journal of an earlier run
  int items_finished = 0;            // finished in this run
  long journal_discarded_bytes = 0;  // a torn last record of an earlier run, discarded
  bool stopped = false;              // stop_requested: results not written; run again to continue
  int threads = 0;
  double seconds = 0.0;
};

// Throws std::invalid_argument for bad input found before the run (unreadable data, invalid options).
StudyRunSummary RunStudy(const Study& study, const std::string& out_dir, const StudyRunOptions& options,
                         const MethodRegistries& registries = MethodRegistries());

// "2/5" -> (2, 5); throws std::invalid_argument otherwise.
void ParseShard(const std::string& text, int* index, int* count);

}  // namespace kincal
