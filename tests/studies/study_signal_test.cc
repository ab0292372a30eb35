// `kincal study` stopped by a real signal: SIGTERM stops it with status 143 and a consistent
// journal; SIGKILL at any moment loses at most the items in flight; the same command then completes the study
// with the bytes of an uninterrupted run.
#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "tests/studies/study_test_util.h"

namespace kincal {
namespace {

using testing::ReadText;
using testing::TempDir;

// Library methods only (the command line knows no test doubles); about 0.3 s per work item.
std::string StudyYaml() {
  return "name: signals\nseed: 11\ntrials: 8\n" + testing::SeedRobotsYaml() +
         "datasets:\n"
         "  - name: random\n"
         "    simulate: {protocol: random, poses: 60, noise: 10um}\n"
         "estimators: [least_squares]\n"
         "compensators: [jacobian]\n"
         "validation:\n"
         "  - {name: targets, random_targets: 150}\n";
}

int JournalRecords(const std::string& dir) {
  std::ifstream in(dir + "/study.journal");
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) ++lines;  // a torn last line counts too: whole records are fewer
  return lines - 1;
}

pid_t StartStudy(const std::string& study, const std::string& out) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execl(KINCAL_CLI, KINCAL_CLI, "study", study.c_str(), "--out", out.c_str(), "--threads", "2",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

TEST(StudySignalTest, SigtermAndSigkillThenTheSameCommandEqualsAnUninterruptedRun) {
  TempDir tmp;
  const std::string study = tmp.path("signals.yaml");
  std::ofstream(study) << StudyYaml();
  const auto whole = testing::RunKincal("study " + study + " --out " + tmp.path("whole") + " --threads 2");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const int items = 16;  // 8 trials x (none, least_squares)
  ASSERT_EQ(JournalRecords(tmp.path("whole")), items);

  for (int sig : {SIGTERM, SIGKILL}) {
    SCOPED_TRACE(sig);
    const std::string out = tmp.path("stopped" + std::to_string(sig));
    const pid_t pid = StartStudy(study, out);
    ASSERT_GT(pid, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (JournalRecords(out) < 2 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_EQ(kill(pid, sig), 0);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    if (sig == SIGTERM) {
      ASSERT_TRUE(WIFEXITED(status));
      EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
      EXPECT_FALSE(std::filesystem::exists(out + "/results.csv"));
    } else {
      ASSERT_TRUE(WIFSIGNALED(status));
    }
    const int done = JournalRecords(out);
    EXPECT_GE(done, 2);
    EXPECT_LT(done, items) << "the run ended before the signal: make the study longer";

    const auto resumed = testing::RunKincal("study " + study + " --out " + out + " --threads 2");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("from the journal of an earlier run"), std::string::npos) << resumed.out;
    EXPECT_NE(resumed.err.find("resuming:"), std::string::npos) << resumed.err;
    for (const char* file : {"study.json", "results.csv", "parameters.csv", "convergence.csv", "iso9283.csv"}) {
      SCOPED_TRACE(file);
      EXPECT_EQ(ReadText(out + "/" + file), ReadText(tmp.path("whole") + "/" + file));
    }
    EXPECT_EQ(JournalRecords(out), items);
  }

  // A journal of this study is refused for another one, with exit status 2 and one line naming it.
  std::ofstream(tmp.path("other.yaml")) << StudyYaml() << "description: another study\n";
  const auto refused = testing::RunKincal("study " + tmp.path("other.yaml") + " --out " + tmp.path("whole"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("study.journal: written by a different study"), std::string::npos) << refused.err;
}

}  // namespace
}  // namespace kincal
