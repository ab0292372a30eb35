#include "studies/progress.h"

#include <cmath>
#include <cstdio>

#include <unistd.h>

namespace kincal {

bool StderrIsTerminal() { return ::isatty(2) == 1; }

ProgressReporter::ProgressReporter(std::ostream* out, bool interactive, int total, std::string what)
    : out_(out),
      interactive_(interactive),
      total_(total),
      what_(std::move(what)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
  if (out_ && interactive_) Draw(false);
}

std::string ProgressReporter::FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--";
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld", s / 60, s % 60);
  return buffer;
}

void ProgressReporter::Done(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  done_ += count;
  if (!out_) return;
  const auto now = std::chrono::steady_clock::now();
  if (interactive_) {
    // Redraw at most ten times a second, and always at the end.
    if (done_ >= total_ || now - last_draw_ > std::chrono::milliseconds(100)) Draw(false);
    return;
  }
  const int tenth = total_ > 0 ? done_ * 10 / total_ : 10;
  if (tenth > last_tenth_) {
    last_tenth_ = tenth;
    Draw(false);
  }
}

void ProgressReporter::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_ || !out_) return;
  finished_ = true;
  if (interactive_) {
    Draw(true);
    *out_ << "\n";
    out_->flush();
  }
}

void ProgressReporter::Draw(bool final) {
  last_draw_ = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(last_draw_ - start_).count();
  const double left = done_ > 0 ? elapsed / done_ * (total_ - done_) : NAN;
  char line[256];
  if (interactive_) {
    constexpr int kWidth = 30;
    const int filled = total_ > 0 ? done_ * kWidth / total_ : kWidth;
    std::string bar(filled, '#');
    bar += std::string(kWidth - filled, '.');
    std::snprintf(line, sizeof(line), "\r[%s] %d/%d %s, %s elapsed, %s left ", bar.c_str(), done_, total_,
                  what_.c_str(), FormatDuration(elapsed).c_str(), final ? "0:00" : FormatDuration(left).c_str());
    *out_ << line;
  } else {
    std::snprintf(line, sizeof(line), "%d/%d %s done, %s elapsed, about %s left\n", done_, total_, what_.c_str(),
                  FormatDuration(elapsed).c_str(), FormatDuration(left).c_str());
    *out_ << line;
  }
  out_->flush();
}

}  // namespace kincal
