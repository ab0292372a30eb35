// Resumable studies: a study stopped part way and run again writes the bytes of an uninterrupted
// run, sharded or not, without redoing a journaled item; a torn last record is discarded; a journal of
// another study is refused. And failing methods: an item whose estimator or compensator throws or
// returns NaN is marked failed with its reason, and the study goes on.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <fstream>

#include <sys/resource.h>

#include <gtest/gtest.h>

#include "framework/error.h"
#include "studies/journal.h"
#include "studies/report.h"
#include "studies/results_files.h"
#include "studies/runner.h"
#include "tests/studies/study_test_util.h"
#include "tests/studies/test_methods.h"

namespace kincal {
namespace {

using testing::kDeterministicFiles;
using testing::ReadText;
using testing::ReportWithoutTimes;
using testing::TempDir;

void ExpectSameResults(const std::string& a, const std::string& b, bool report = true) {
  for (const char* file : kDeterministicFiles) {
    SCOPED_TRACE(file);
    const std::string text = ReadText(a + "/" + file);
    EXPECT_FALSE(text.empty());
    EXPECT_EQ(text, ReadText(b + "/" + file));
  }
  // timings.csv: the same rows (keys), whatever the times.
  EXPECT_EQ(ReadResultTable(a + "/timings.csv").rows.size(), ReadResultTable(b + "/timings.csv").rows.size());
  if (report) {
    EXPECT_EQ(ReportWithoutTimes(a), ReportWithoutTimes(b));
  }
}

std::string JournalOf(const std::string& dir) { return dir + "/" + StudyJournal::kFileName; }

int Records(const std::string& dir) {
  const std::string text = ReadText(JournalOf(dir));
  return static_cast<int>(std::count(text.begin(), text.end(), '\n')) - 1;
}

class StudyResumeTest : public ::testing::Test {
 protected:
  StudyResumeTest()
      : registries_(testing::MakeTestRegistries(testing::SeedTruth())),
        study_(ParseStudy(testing::SmallStudyYaml(), "small.yaml", registries_.view())) {}

  // Runs; with `stop_after` >= 0 a stop is requested once that many items have started (one thread).
  StudyRunSummary Run(const std::string& dir, int stop_after = -1, int shard = 1, int shards = 1, int threads = 1) {
    StudyRunOptions o;
    o.threads = threads;
    o.shard_index = shard;
    o.shard_count = shards;
    auto polls = std::make_shared<std::atomic<int>>(0);
    if (stop_after >= 0) o.stop_requested = [polls, stop_after]() { return (*polls)++ >= stop_after; };
    return RunStudy(study_, dir, o, registries_.view());
  }

  testing::TestRegistries registries_;
  Study study_;
};

TEST_F(StudyResumeTest, StoppedThenResumedEqualsUninterruptedAndRedoesNothing) {
  TempDir tmp;
  const StudyRunSummary whole = Run(tmp.path("whole"));
  EXPECT_FALSE(whole.stopped);
  ASSERT_GT(whole.items_run, 6);

  const std::string dir = tmp.path("stopped");
  const StudyRunSummary first = Run(dir, 3);
  EXPECT_TRUE(first.stopped);
  EXPECT_EQ(first.items_finished, 3);
  EXPECT_EQ(Records(dir), 3);
  EXPECT_FALSE(std::filesystem::exists(dir + "/results.csv"));  // nothing half written
  const StudyRunSummary second = Run(dir, 2);                   // stopped again
  EXPECT_TRUE(second.stopped);
  EXPECT_EQ(second.items_resumed, 3);
  EXPECT_EQ(second.items_finished, 2);
  const StudyRunSummary last = Run(dir, -1, 1, 1, 3);
  EXPECT_FALSE(last.stopped);
  EXPECT_EQ(last.items_resumed, 5);
  EXPECT_EQ(last.items_finished, whole.items_run - 5);
  EXPECT_EQ(Records(dir), whole.items_run);
  ExpectSameResults(tmp.path("whole"), dir);

  // Once complete, the same run again only rewrites the files.
  const StudyRunSummary again = Run(dir);
  EXPECT_EQ(again.items_finished, 0);
  EXPECT_EQ(again.items_resumed, whole.items_run);
  ExpectSameResults(tmp.path("whole"), dir);
}

TEST_F(StudyResumeTest, StoppedShardsResumedAndMergedEqualTheUnshardedRun) {
  TempDir tmp;
  Run(tmp.path("whole"));
  std::vector<std::string> dirs;
  for (int i = 1; i <= 3; ++i) {
    dirs.push_back(tmp.path("shard" + std::to_string(i)));
    if (i != 2) {
      EXPECT_TRUE(Run(dirs.back(), 1, i, 3).stopped);
      EXPECT_EQ(Records(dirs.back()), 1);
    }
    EXPECT_FALSE(Run(dirs.back(), -1, i, 3).stopped);
  }
  MergeShards(dirs, tmp.path("merged"));
  WriteReport(tmp.path("merged"));
  ExpectSameResults(tmp.path("whole"), tmp.path("merged"));
}

TEST_F(StudyResumeTest, TornLastRecordIsDiscardedAndItsItemRunsAgain) {
  TempDir tmp;
  Run(tmp.path("whole"));
  for (int cut : {1, 20, 200}) {
    SCOPED_TRACE(cut);
    const std::string dir = tmp.path("torn" + std::to_string(cut));
    Run(dir, 4);
    // A SIGKILL or power cut in the middle of the 4th record: its tail is missing.
    const std::string text = ReadText(JournalOf(dir));
    std::filesystem::resize_file(JournalOf(dir), text.size() - cut);
    const StudyRunSummary resumed = Run(dir);
    EXPECT_EQ(resumed.items_resumed, 3);
    EXPECT_EQ(resumed.journal_discarded_bytes, static_cast<long>(text.size() - cut - (text.rfind("\nitem ") + 1)));
    ExpectSameResults(tmp.path("whole"), dir);
  }
  // A journal cut inside its first line starts over.
  const std::string dir = tmp.path("header");
  Run(dir, 1);
  std::filesystem::resize_file(JournalOf(dir), 10);
  EXPECT_EQ(Run(dir).items_resumed, 0);
  ExpectSameResults(tmp.path("whole"), dir);
}

TEST_F(StudyResumeTest, DamagedRecordBeforeTheLastIsAnError) {
  TempDir tmp;
  const std::string dir = tmp.path("r");
  Run(dir, 3);
  std::string text = ReadText(JournalOf(dir));
  const size_t second = text.find("\nitem ", text.find("\nitem ") + 1);
  text[text.find("[", second) + 3] ^= 1;  // a flipped bit inside the second of three records
  std::ofstream(JournalOf(dir), std::ios::binary) << text;
  try {
    Run(dir);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("damaged record"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(JournalOf(dir)), std::string::npos) << e.what();
  }
}

TEST_F(StudyResumeTest, JournalOfAnotherStudyOrShardIsRefused) {
  TempDir tmp;
  const std::string dir = tmp.path("r");
  Run(dir, 2);
  const std::string before = ReadText(JournalOf(dir));
  const auto expect_refused = [&](const std::function<void()>& run) {
    try {
      run();
      FAIL() << "expected the journal to be refused";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("different study"), std::string::npos) << e.what();
    }
    EXPECT_EQ(ReadText(JournalOf(dir)), before);  // untouched
    EXPECT_FALSE(std::filesystem::exists(dir + "/results.csv"));
  };
  expect_refused([&]() { Run(dir, -1, 1, 2); });  // another shard
  study_.seed = 8;
  expect_refused([&]() { Run(dir); });  // another seed
  study_ = ParseStudy(testing::SmallStudyYaml() + "description: edited\n", "small.yaml", registries_.view());
  expect_refused([&]() { Run(dir); });  // another study file text
  // Not a journal at all.
  std::filesystem::create_directories(tmp.path("x"));
  std::ofstream(tmp.path("x/" + std::string(StudyJournal::kFileName))) << "hello, world\n";
  EXPECT_THROW(Run(tmp.path("x")), std::invalid_argument);
  // A journal of another format version (its records hold other columns), whatever its fingerprint.
  std::string old_version = before;
  old_version.replace(old_version.find("journal v2 "), 11, "journal v1 ");
  std::filesystem::create_directories(tmp.path("v1"));
  std::ofstream(tmp.path("v1/" + std::string(StudyJournal::kFileName))) << old_version;
  try {
    Run(tmp.path("v1"));
    ADD_FAILURE() << "expected the journal of another version to be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("another kincal version (kincal study journal v1"), std::string::npos)
        << e.what();
  }
}

// A journal that cannot be written (here: the file-size limit, as a full disk would) is an IoError naming
// the journal and the system's reason, which `kincal study` answers with exit status 2 and that line.
TEST_F(StudyResumeTest, AJournalWriteThatFailsIsAnIoErrorNamingTheJournal) {
  TempDir tmp;
  const std::string dir = tmp.path("out");
  StudyJournal journal(dir, "fingerprint", 3);
  const auto size = std::filesystem::file_size(JournalOf(dir));
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  rlimit limit = saved;
  limit.rlim_cur = static_cast<rlim_t>(size);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message;
  try {
    journal.Append(1, StudyTables());
  } catch (const IoError& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_EQ(message.rfind(JournalOf(dir) + ": cannot write the journal: ", 0), 0u) << message;
  EXPECT_NE(message.find(std::strerror(EFBIG)), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST_F(StudyResumeTest, JournalRowsRoundTripAnyText) {
  StudyTables t;
  t.results.rows = {{"0", "a\"b\\c", "line\nbreak", ""}, {"1"}};
  t.iso9283.rows = {{"é", "\t"}};
  const std::string payload = EncodeJournalRows(t);
  EXPECT_EQ(payload.find('\n'), std::string::npos);
  const StudyTables back = DecodeJournalRows(payload);
  EXPECT_EQ(back.results.rows, t.results.rows);
  EXPECT_EQ(back.iso9283.rows, t.iso9283.rows);
  EXPECT_TRUE(back.timings.rows.empty());
  EXPECT_THROW(DecodeJournalRows("[[], []]"), std::invalid_argument);
  EXPECT_THROW(DecodeJournalRows("[[[1]], [], [], [], []]"), std::invalid_argument);
}

// Methods that throw or return NaN fail their rows with the reason; everything else is scored.
TEST(StudyFailuresTest, ThrowingOrNanMethodsMarkTheirItemsFailedAndTheStudyGoesOn) {
  const testing::TestRegistries registries = testing::MakeTestRegistries(testing::SeedTruth(), true);
  const std::string yaml = "name: failures\nseed: 3\n" + testing::SeedRobotsYaml() +
                           "datasets:\n"
                           "  - name: random\n"
                           "    simulate: {protocol: random, poses: 24, noise: 10um}\n"
                           "estimators: [base_kabsch, nan, throws]\n"
                           "compensators: [jacobian_ik, throws, nan]\n"
                           "validation:\n"
                           "  - {name: targets, random_targets: 6}\n";
  const Study study = ParseStudy(yaml, "failures.yaml", registries.view());
  TempDir tmp;
  StudyRunOptions o;
  o.threads = 2;
  const StudyRunSummary s = RunStudy(study, tmp.path("r"), o, registries.view());
  EXPECT_EQ(s.items_run, 4);  // none + 3 pipelines
  const ResultTable t = ReadResultTable(tmp.path("r") + "/results.csv");
  const int est = t.Column("estimator"), comp = t.Column("compensator"), status = t.Column("status"),
            note = t.Column("note"), mean = t.Column("position_error_mean_mm");
  int failed = 0, scored = 0;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const std::string& e = t.Text(r, est);
    const std::string& c = t.Text(r, comp);
    SCOPED_TRACE(e + "/" + c);
    if (e == "nan" && c != "throws" && c != "nan") {
      // The estimator interface catches a non-finite result itself (never a NaN written): the
      // estimate is failed, the start robot is kept and scored, and the note says why.
      ++failed;
      EXPECT_EQ(t.Text(r, status), "estimate_failed");
      EXPECT_NE(t.Text(r, note).find("non-finite (NaN or infinite) parameters"), std::string::npos) << t.Text(r, note);
      EXPECT_EQ(t.Text(r, mean).find("nan"), std::string::npos);
    } else if (e == "nan" || e == "throws" || c == "throws" || c == "nan") {
      ++failed;
      EXPECT_EQ(t.Text(r, status), "failed");
      EXPECT_EQ(t.Text(r, mean), "");  // no score, never a NaN
      const std::string& why = t.Text(r, note);
      if (e == "nan") {
        EXPECT_NE(why.find("compensator " + c + ":"), std::string::npos) << why;
      } else if (e == "throws") {
        EXPECT_NE(why.find("estimator throws: throws: this estimator needs data"), std::string::npos) << why;
      } else if (c == "throws") {
        EXPECT_NE(why.find("compensator throws: an exception that is not a std::exception"), std::string::npos) << why;
      } else {
        EXPECT_NE(why.find("compensator nan: returned a non-finite solution at target 1 of targets"), std::string::npos)
            << why;
      }
    } else {
      ++scored;
      EXPECT_NE(t.Text(r, status), "failed");
      EXPECT_FALSE(t.Text(r, mean).empty());
    }
  }
  EXPECT_GT(failed, 0);
  EXPECT_EQ(scored, 2 * 3);  // estimators none and base_kabsch, each with compensators "-", none and jacobian_ik
  const std::string report = ReadText(tmp.path("r") + "/report.md");
  EXPECT_NE(report.find("failed"), std::string::npos);
  EXPECT_NE(report.find("non-finite (NaN or infinite) parameters"), std::string::npos);
}

}  // namespace
}  // namespace kincal
