// ShortLine (framework/short_line.h): a long list is cut after a whole item and the count of the rest is exact;
// SplitComma and OptionsPerMethod (framework/method_options.h), which the command line and Python share;
// Median (framework/median.h).
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "framework/median.h"
#include "framework/method_options.h"
#include "framework/short_line.h"

namespace kincal {
namespace {

// "prefix: p0 (a, b), p1 (a, b), ..." with n items.
std::string NameList(int n) {
  std::string text = "held (add poses, or priors): ";
  for (int i = 0; i < n; ++i) text += (i ? ", " : "") + std::string("p") + std::to_string(i) + " (sd 1, trades a, b)";
  return text;
}

TEST(ShortLine, CutsAfterAWholeItemAndCountsTheRest) {
  const std::string full = NameList(200);
  ASSERT_GT(full.size(), 3000u);
  const std::string short_line = ShortLine(full, 240, " (all in R.json)");
  EXPECT_LE(short_line.size(), 240u + 40u);
  // The kept part is a prefix of the message ending with a whole item, and kept + counted = every item.
  const size_t cut = short_line.find(" ... and ");
  ASSERT_NE(cut, std::string::npos) << short_line;
  EXPECT_EQ(full.compare(0, cut, short_line, 0, cut), 0);
  EXPECT_EQ(short_line[cut - 1], ')');
  int kept = 0;
  for (size_t at = short_line.find(" (sd 1"); at < cut; at = short_line.find(" (sd 1", at + 1)) ++kept;
  const int more = std::stoi(short_line.substr(cut + 9));
  EXPECT_EQ(kept + more, 200) << short_line;
  EXPECT_EQ(short_line.substr(short_line.size() - 16), " (all in R.json)");
}

TEST(ShortLine, SpaceSeparatedListsAndShortTextsStay) {
  EXPECT_EQ(ShortLine("short", 240, " x"), "short");
  std::string freed = "freed";
  for (int i = 0; i < 100; ++i) freed += " alpha_" + std::to_string(i);
  const std::string s = ShortLine(freed, 60, "");
  const size_t cut = s.find(" ... and ");
  ASSERT_NE(cut, std::string::npos) << s;
  const int kept = static_cast<int>(std::count(s.begin(), s.begin() + static_cast<long>(cut), ' '));
  EXPECT_EQ(kept + std::stoi(s.substr(cut + 9)), 100) << s;
}

TEST(OptionsPerMethod, KeyedOrDirectAndOneLineErrors) {
  EXPECT_EQ(SplitComma("a,b,,c"), (std::vector<std::string>{"a", "b", "", "c"}));
  const YAML::Node keyed = YAML::Load("{least_squares: {max_iterations: 5}, geometric: {}}");
  const auto per = OptionsPerMethod(keyed, {"geometric", "ratio_regression", "least_squares"}, "O.yaml");
  ASSERT_EQ(per.size(), 3u);
  EXPECT_TRUE(per[0].IsMap());
  EXPECT_TRUE(per[1].IsNull());  // left out: its defaults
  EXPECT_EQ(per[2]["max_iterations"].as<int>(), 5);
  const YAML::Node direct = YAML::Load("{max_iterations: 7}");
  EXPECT_EQ(OptionsPerMethod(direct, {"least_squares"}, "O.yaml")[0]["max_iterations"].as<int>(), 7);
  try {
    OptionsPerMethod(direct, {"geometric", "least_squares"}, "O.yaml");
    FAIL() << "options of several methods not keyed by name";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("O.yaml:1:1: with several methods", 0), 0u) << e.what();
  }
  try {
    OptionsPerMethod(YAML::Load("[1, 2]"), {"geometric"}, "options", 0);
    FAIL() << "a list is not options";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "options: expected a map of options");
  }
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// Median and Quantile (framework/median.h) against a sort of the finite values, odd and even counts, at
// random.
TEST(Median, TheMiddleOfTheSortedFiniteValues) {
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_TRUE(std::isnan(Median({NAN, INFINITY})));
  EXPECT_EQ(Median({3.0}), 3.0);
  EXPECT_EQ(Median({4.0, NAN, 1.0}), 2.5);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> value(-5.0, 5.0);
  for (int n = 1; n <= 40; ++n) {
    std::vector<double> v(static_cast<size_t>(n));
    for (double& x : v) x = value(random);
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const double expected = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    EXPECT_EQ(Median(v), expected) << n;
    // Quantile interpolates between ranks: its 0.5 is the median, its ends the extremes, and a quarter of
    // the way between the ranks k and k + 1 lies a quarter of the gap above rank k.
    EXPECT_NEAR(Quantile(sorted, 0.5), expected, 1e-15 * 5) << n;
    EXPECT_EQ(Quantile(sorted, 0.0), sorted.front());
    EXPECT_EQ(Quantile(sorted, 1.0), sorted.back());
    if (n > 1) {
      const int k = n / 3;
      const double f = (k + 0.25) / (n - 1);
      EXPECT_NEAR(Quantile(sorted, f), sorted[k] + 0.25 * (sorted[k + 1] - sorted[k]), 1e-14) << n;
    }
  }
}

}  // namespace
}  // namespace kincal
