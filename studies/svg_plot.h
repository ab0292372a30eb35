#pragma once
// A small SVG plot writer for the study reports (no plotting dependency is available): line and scatter
// plots with error bars, box plots, categorical or numeric x, linear or logarithmic axes, legends and
// several panels stacked in one figure. The output aims at what a paper prints: a frame with ticks
// outside, light grid lines, tick labels on "nice" numbers (1, 2, 2.5, 5 x 10^k, or decades on log
// axes), axis labels with units, a colour-blind-safe palette (Okabe and Ito) plus marker shapes and
// dashes so that series stay distinct in grey print.
#include <limits>
#include <string>
#include <vector>

namespace kincal::svg {

struct Series {
  std::string label;                  // legend entry; "" = not in the legend
  std::vector<double> x, y;           // with categorical axes, x is the category index (offsets allowed)
  std::vector<double> y_low, y_high;  // error bar ends (absolute), same size as y, or empty
  bool lines = true;                  // join the points
  bool markers = true;
  int style = -1;      // colour, marker and dash index; -1 = the series' position
  bool muted = false;  // drawn grey and dashed (a reference such as "before")
};

// One box of a box plot, at category index `position`.
struct Box {
  double position = 0.0;
  double low = 0.0, q1 = 0.0, median = 0.0, q3 = 0.0, high = 0.0;  // whisker, box, whisker
  double extreme = std::numeric_limits<double>::quiet_NaN();  // drawn as a hollow circle (e.g. the maximum), NaN = none
  int style = 0;
};

struct Axes {
  std::string title;
  std::string x_label, y_label;  // with units, e.g. "position error (mm)"
  bool log_x = false, log_y = false;
  std::vector<std::string> categories;  // non-empty: categorical x axis, one slot per category
  std::vector<Series> series;
  std::vector<Box> boxes;
  bool zero_line = false;  // a horizontal line at y = 0 (signed errors)
  std::string note;        // one small line under the panel (e.g. what a box shows)
};

struct Figure {
  std::string title;
  std::vector<Axes> panels;  // stacked top to bottom
};

// The whole SVG document.
std::string RenderSvg(const Figure& figure);

// Nice tick positions covering [low, high] with at most about `target` ticks.
std::vector<double> LinearTicks(double low, double high, int target);
// Tick label text for a value on a linear axis whose ticks are `step` apart.
std::string FormatTick(double value, double step);

}  // namespace kincal::svg
