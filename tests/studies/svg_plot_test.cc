// The SVG plot writer: tick choice, labels, and a well-formed document.
#include <cmath>
#include <regex>

#include <gtest/gtest.h>

#include "studies/svg_plot.h"

namespace kincal::svg {
namespace {

TEST(LinearTicks, AreNiceNumbersCoveringTheRange) {
  EXPECT_EQ(LinearTicks(0.0, 1.0, 6), (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0}));
  const std::vector<double> t = LinearTicks(-0.37, 2.9, 6);
  EXPECT_LE(t.front(), -0.37);
  EXPECT_GE(t.back(), 2.9);
  const double step = t[1] - t[0];
  EXPECT_NEAR(step, 1.0, 1e-12);  // 3.27 / 5 = 0.65 -> 1
  for (double a : {1e-7, 3e-3, 42.0, 7e5}) {
    const std::vector<double> u = LinearTicks(0.0, a, 6);
    ASSERT_GE(u.size(), 2u);
    const double s = u[1] - u[0];
    const double mantissa = s / std::pow(10.0, std::floor(std::log10(s)));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 || std::abs(mantissa - 2.5) < 1e-9 ||
                std::abs(mantissa - 5) < 1e-9)
        << s;
    EXPECT_LE(u.size(), 7u);
    EXPECT_GE(u.back(), a);
  }
}

TEST(FormatTick, UsesTheDecimalsOfTheStep) {
  EXPECT_EQ(FormatTick(0.6000000000000001, 0.2), "0.6");
  EXPECT_EQ(FormatTick(0.75, 0.25), "0.75");
  EXPECT_EQ(FormatTick(20.0, 10.0), "20");
  EXPECT_EQ(FormatTick(-1e-17, 0.5), "0.0");
  EXPECT_EQ(FormatTick(3e-6, 1e-6), "3e-06");
}

int Count(const std::string& text, const std::regex& r) {
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), r), std::sregex_iterator()));
}

TEST(RenderSvg, DrawsAxesLabelsLegendAndEscapesText) {
  Figure f;
  f.title = "Errors <before & after>";
  Axes line;
  line.title = "convergence";
  line.x_label = "iteration";
  line.y_label = "position error (mm)";
  line.log_y = true;
  Series s;
  s.label = "a / b";
  s.x = {0, 1, 2, 3};
  s.y = {3.0, 1e-3, 1e-9, 0.0};  // the zero cannot be drawn on a log axis and is left out
  line.series.push_back(s);
  Series e;
  e.label = "with bars";
  e.x = {0, 1};
  e.y = {1.0, 2.0};
  e.y_low = {0.5, 1.5};
  e.y_high = {1.5, 2.5};
  line.series.push_back(e);
  f.panels.push_back(line);
  Axes box;
  box.y_label = "orientation error (deg)";
  box.categories = {"before", "a very long method name / compensator"};
  box.boxes.push_back({0.0, 1, 2, 3, 4, 5, 6, 0});
  box.boxes.push_back({1.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 1});
  box.note = "box: 25-75 %";
  f.panels.push_back(box);
  const std::string svg = RenderSvg(f);
  EXPECT_NE(svg.find("Errors &lt;before &amp; after&gt;"), std::string::npos);
  for (const char* text : {">iteration<", ">position error (mm)<", ">orientation error (deg)<", ">a / b<",
                           ">with bars<", ">box: 25-75 %<", "rotate(-35"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  // Log axis from below 1e-9 (a margin keeps points off the frame) to 10: decades labelled with superscripts,
  // every second one on so wide an axis.
  EXPECT_NE(svg.find(">10<tspan dy=\"-5\" font-size=\"8\">-10</tspan>"), std::string::npos);
  EXPECT_EQ(svg.find(">10<tspan dy=\"-5\" font-size=\"8\">-9</tspan>"), std::string::npos);
  EXPECT_EQ(Count(svg, std::regex("<polyline")), 2);
  EXPECT_EQ(Count(svg, std::regex(R"(<([a-zA-Z]+)[ >])")),
            Count(svg, std::regex("/>")) + Count(svg, std::regex(R"(</[a-zA-Z]+>)")));
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

}  // namespace
}  // namespace kincal::svg
