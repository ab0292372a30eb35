#include "studies/runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "framework/error.h"
#include "studies/evaluation.h"
#include "studies/journal.h"
#include "studies/progress.h"
#include "studies/report.h"
#include "studies/results_files.h"

namespace kincal {

bool StudyRunOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (threads < 0) return fail("threads must be >= 0");
  if (shard_count < 1 || shard_index < 1 || shard_index > shard_count) {
    return fail("shard must be i/N with 1 <= i <= N, got " + std::to_string(shard_index) + "/" +
                std::to_string(shard_count));
  }
  return true;
}

void ParseShard(const std::string& text, int* index, int* count) {
  int i = 0, n = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &i, &n, &tail) != 2 || n < 1 || i < 1 || i > n) {
    ThrowInputError("--shard: expected i/N with 1 <= i <= N (e.g. 2/8), got '" + text + "'");
  }
  *index = i;
  *count = n;
}

namespace {

// Runs the work items mine[todo[k]] on `threads` threads (the caller's among them), each item's rows into
// (*rows)[todo[k]] and the journal as it finishes; stops taking items when a stop is requested (*stopped)
// or an item fails, whose exception is rethrown once every thread has ended. Returns the items finished.
int RunItems(const Study& study, const StudyEvaluator& evaluator, const std::vector<WorkItem>& mine,
             const std::vector<size_t>& todo, int threads, const StudyRunOptions& options, StudyJournal* journal,
             ProgressReporter* reporter, std::vector<StudyTables>* rows_out, bool* stopped_out) {
  std::vector<StudyTables>& rows = *rows_out;
  ProgressReporter& progress = *reporter;
  std::atomic<size_t> next{0};
  std::atomic<int> finished{0};
  std::atomic<bool> stopped{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&]() {
    while (true) {
      if (options.stop_requested && options.stop_requested()) {
        stopped = true;
        return;
      }
      const size_t k = next.fetch_add(1);
      if (k >= todo.size()) return;
      try {
        const ItemResult result = evaluator.Run(mine[todo[k]]);  // never throws for a method's failure
        rows[todo[k]] = MakeStudyTables(study, evaluator.variants(), {result});
        if (journal) journal->Append(mine[todo[k]].index, rows[todo[k]]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = todo.size();
        return;
      }
      ++finished;
      progress.Done();
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  progress.Finish();
  if (failure) std::rethrow_exception(failure);
  *stopped_out = stopped;
  return finished;
}

// The tables of an uninterrupted run: its headers, then every item's rows in item order.
StudyTables InItemOrder(const Study& study, const StudyEvaluator& evaluator, std::vector<StudyTables>* rows) {
  StudyTables tables = MakeStudyTables(study, evaluator.variants(), {});
  const auto to = tables.All();
  for (StudyTables& item : *rows) {
    const auto from = item.All();
    for (int f = 0; f < StudyTables::kCount; ++f) {
      for (auto& row : from[f]->rows) to[f]->rows.push_back(std::move(row));
    }
  }
  return tables;
}

}  // namespace

StudyRunSummary RunStudy(const Study& study, const std::string& out_dir, const StudyRunOptions& options,
                         const MethodRegistries& registries) {
  std::string why;
  if (!options.IsValid(&why)) ThrowInputError("study: " + why);
  const auto t0 = std::chrono::steady_clock::now();
  const StudyEvaluator evaluator(study, registries);
  const int num_items = static_cast<int>(evaluator.items().size());

  std::vector<WorkItem> mine;
  for (const WorkItem& w : evaluator.items()) {
    if (w.index % options.shard_count == options.shard_index - 1) mine.push_back(w);
  }
  std::unique_ptr<StudyJournal> journal;
  if (options.journal) {
    journal = std::make_unique<StudyJournal>(out_dir, StudyFingerprint(study, options.shard_index, options.shard_count),
                                             num_items);
  }
  // Each item's rows of the five tables, in the order of `mine`: from the journal or computed now.
  std::vector<StudyTables> rows(mine.size());
  std::vector<size_t> todo;
  StudyRunSummary summary;
  for (size_t k = 0; k < mine.size(); ++k) {
    const auto recorded =
        journal ? journal->recorded().find(mine[k].index) : std::map<int, StudyTables>::const_iterator();
    if (journal && recorded != journal->recorded().end()) {
      rows[k] = recorded->second;
      ++summary.items_resumed;
    } else {
      todo.push_back(k);
    }
  }
  if (journal && summary.items_resumed != static_cast<int>(journal->recorded().size())) {
    ThrowInputError(journal->path() + ": holds work items that are not in shard " +
                    std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count));
  }

  int threads = options.threads > 0 ? options.threads : study.threads;
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min<int>(threads, static_cast<int>(todo.size())));

  std::string what = "work items";
  if (options.shard_count > 1)
    what += " of shard " + std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count);
  if (options.progress && summary.items_resumed > 0) {
    *options.progress << "resuming: " << summary.items_resumed << " of " << mine.size() << " " << what
                      << " already done (" << journal->path() << ")\n";
  }
  if (options.progress && journal && journal->discarded_bytes() > 0) {
    *options.progress << "discarded the torn last record of " << journal->path() << " (" << journal->discarded_bytes()
                      << " bytes): that item runs again\n";
  }
  ProgressReporter progress(options.progress, options.interactive, static_cast<int>(todo.size()), what);
  bool stopped = false;
  const int finished =
      RunItems(study, evaluator, mine, todo, threads, options, journal.get(), &progress, &rows, &stopped);

  summary.items_total = num_items;
  summary.items_run = static_cast<int>(mine.size());
  summary.items_finished = finished;
  summary.journal_discarded_bytes = journal ? journal->discarded_bytes() : 0;
  summary.threads = threads;
  summary.stopped = stopped && summary.items_resumed + summary.items_finished < summary.items_run;
  if (!summary.stopped) {
    StudyTables tables = InItemOrder(study, evaluator, &rows);
    if (options.shard_count == 1) FlagWorseThanGeometry(&tables.results);  // merge flags the shards'
    const nlohmann::json manifest = StudyManifest(study, evaluator.variants(), num_items);
    WriteStudyFiles(out_dir, manifest, std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count),
                    tables);
    if (options.shard_count == 1 && options.write_report) WriteReport(out_dir);
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace kincal
