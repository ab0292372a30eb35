// Progress on stderr: plain lines for logs, a bar redrawn in place on terminals.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "studies/progress.h"

namespace kincal {
namespace {

TEST(Progress, PlainLinesAtEveryTenthOfTheWork) {
  std::ostringstream out;
  ProgressReporter p(&out, false, 25, "work items");
  for (int i = 0; i < 25; ++i) p.Done();
  p.Finish();
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 10);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_NE(text.find("25/25 work items done"), std::string::npos);
  EXPECT_NE(text.find("left"), std::string::npos);
}

TEST(Progress, BarRedrawnInPlaceOnATerminal) {
  std::ostringstream out;
  ProgressReporter p(&out, true, 4, "work items");
  for (int i = 0; i < 4; ++i) p.Done();
  p.Finish();
  const std::string text = out.str();
  EXPECT_EQ(text.rfind('\r'), text.rfind("\r[##############################] 4/4"));
  EXPECT_NE(text.rfind("0:00 left"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
}

TEST(Progress, Durations) {
  EXPECT_EQ(ProgressReporter::FormatDuration(65.4), "1:05");
  EXPECT_EQ(ProgressReporter::FormatDuration(3725), "1:02:05");
  EXPECT_EQ(ProgressReporter::FormatDuration(NAN), "--");
}

}  // namespace
}  // namespace kincal
