#include "framework/study/runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>

#include "framework/error.h"
#include "framework/study/evaluation.h"
#include "framework/study/progress.h"
#include "framework/study/report.h"
#include "framework/study/results_files.h"

namespace kincal {

bool StudyRunOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (threads < 0) return fail("threads must be >= 0");
  if (shard_count < 1 || shard_index < 1 || shard_index > shard_count) {
    return fail("shard must be i/N with 1 <= i <= N, got " + std::to_string(shard_index) + "/" + std::to_string(shard_count));
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

StudyRunSummary RunStudy(const Study& study, const std::string& out_dir, const StudyRunOptions& options,
                         const MethodRegistries& registries) {
  std::string why;
  if (!options.IsValid(&why)) ThrowInputError("study: " + why);
  const auto t0 = std::chrono::steady_clock::now();
  const StudyEvaluator evaluator(study, registries);

  std::vector<WorkItem> mine;
  for (const WorkItem& w : evaluator.items()) {
    if (w.index % options.shard_count == options.shard_index - 1) mine.push_back(w);
  }
  int threads = options.threads > 0 ? options.threads : study.threads;
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min<int>(threads, static_cast<int>(mine.size())));

  std::string what = "work items";
  if (options.shard_count > 1) what += " of shard " + std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count);
  ProgressReporter progress(options.progress, options.interactive, static_cast<int>(mine.size()), what);
  std::vector<ItemResult> results(mine.size());
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&]() {
    while (true) {
      const size_t k = next.fetch_add(1);
      if (k >= mine.size()) return;
      try {
        results[k] = evaluator.Run(mine[k]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = mine.size();
        return;
      }
      progress.Done();
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  progress.Finish();
  if (failure) std::rethrow_exception(failure);

  const nlohmann::json manifest =
      StudyManifest(study, evaluator.variants(), static_cast<int>(evaluator.items().size()));
  const StudyTables tables = MakeStudyTables(study, evaluator.variants(), results);
  WriteStudyFiles(out_dir, manifest, std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count),
                  tables);
  if (options.shard_count == 1 && options.write_report) WriteReport(out_dir);

  StudyRunSummary summary;
  summary.items_total = static_cast<int>(evaluator.items().size());
  summary.items_run = static_cast<int>(mine.size());
  summary.threads = threads;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace kincal
