#pragma once
// Progress of a long run on stderr: a bar with the time left when stderr is a terminal, plain lines (one
// per tenth of the work) otherwise, so logs of batch jobs stay readable. Thread-safe.
#include <chrono>
#include <mutex>
#include <ostream>
#include <string>

namespace kincal {

class ProgressReporter {
 public:
  // `out` may be null (silent). `interactive`: redraw one line in place (a terminal).
  ProgressReporter(std::ostream* out, bool interactive, int total, std::string what);
  void Done(int count = 1);  // count more units finished
  void Finish();             // ends the bar's line

  // "1:05" style, or "--" when unknown.
  static std::string FormatDuration(double seconds);

 private:
  void Draw(bool final);
  std::ostream* out_;
  bool interactive_;
  int total_;
  int done_ = 0;
  int last_tenth_ = 0;
  std::string what_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
  bool finished_ = false;
};

// Whether stderr is a terminal.
bool StderrIsTerminal();

}  // namespace kincal
