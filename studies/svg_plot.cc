#include "studies/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace kincal::svg {
namespace {

// Okabe & Ito's colour-blind-safe palette (yellow, too pale on white, replaced by wine).
const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#882255", "#000000"};
constexpr int kColours = 8;
constexpr int kShapes = 5;
const char* const kDashes[] = {"", "7 3", "2 2"};
constexpr double kCharWidth = 6.4;  // of 11 px sans-serif text, for layout estimates
constexpr double kPlotHeight = 280.0;

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.2f", v);
  return buffer;
}

struct Scale {
  double lo = 0.0, hi = 1.0;    // data range shown (for log axes, log10 of it)
  double from = 0.0, to = 1.0;  // pixels
  bool log = false;
  double operator()(double v) const {
    const double t = log ? std::log10(v) : v;
    return from + (t - lo) / (hi - lo) * (to - from);
  }
  bool Visible(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
};

struct Tick {
  double value;
  std::string label;  // "" = minor tick
  bool superscript = false;
};

std::vector<Tick> LogTicks(double min_positive, double max, Scale* scale) {
  // Whole decades; one more when a point would sit on the frame (within 2 % of the span).
  const double lo = std::log10(min_positive), hi = std::log10(max);
  const double margin = 0.02 * std::max(1.0, hi - lo);
  int e0 = static_cast<int>(std::floor(lo + 1e-9));
  int e1 = static_cast<int>(std::ceil(hi - 1e-9));
  if (lo - e0 < margin) --e0;
  if (e1 - hi < margin) ++e1;
  if (e1 <= e0) e1 = e0 + 1;
  scale->lo = e0;
  scale->hi = e1;
  scale->log = true;
  const int decades = e1 - e0;
  const int every = decades > 8 ? 2 : 1;
  const bool plain = e0 >= -2 && e1 <= 3;
  std::vector<Tick> ticks;
  for (int e = e0; e <= e1; ++e) {
    const double v = std::pow(10.0, e);
    Tick t{v, "", false};
    if ((e - e0) % every == 0) {
      if (plain) {
        char buffer[32];
        std::snprintf(buffer, sizeof(buffer), "%g", v);
        t.label = buffer;
      } else {
        t.label = std::to_string(e);
        t.superscript = true;
      }
    }
    ticks.push_back(t);
    if (e == e1 || decades > 6) continue;
    for (int m = 2; m <= 9; ++m) {
      Tick minor{m * v, "", false};
      if (decades == 1 && (m == 2 || m == 5)) {
        char buffer[32];
        std::snprintf(buffer, sizeof(buffer), "%g", m * v);
        minor.label = buffer;
      }
      ticks.push_back(minor);
    }
  }
  return ticks;
}

std::vector<Tick> AxisTicks(double lo, double hi, bool log, Scale* scale) {
  if (log) return LogTicks(lo, hi, scale);
  if (!(hi > lo)) {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  // A margin of 3 % keeps points off the frame, except below a zero minimum (error magnitudes start there).
  const double pad = 0.03 * (hi - lo);
  if (lo != 0.0) lo -= pad;
  hi += pad;
  const std::vector<double> values = LinearTicks(lo, hi, 6);
  scale->lo = values.front();
  scale->hi = values.back();
  const double step = values.size() > 1 ? values[1] - values[0] : 1.0;
  std::vector<Tick> ticks;
  for (double v : values) ticks.push_back({v, FormatTick(v, step), false});
  return ticks;
}

// Range of the y data of a panel (only positive values count on a log axis).
void YRange(const Axes& a, double* lo, double* hi) {
  *lo = INFINITY;
  *hi = -INFINITY;
  const auto add = [&](double v) {
    if (!std::isfinite(v) || (a.log_y && v <= 0.0)) return;
    *lo = std::min(*lo, v);
    *hi = std::max(*hi, v);
  };
  for (const auto& s : a.series) {
    for (double v : s.y) add(v);
    for (double v : s.y_low) add(v);
    for (double v : s.y_high) add(v);
  }
  for (const auto& b : a.boxes) {
    for (double v : {b.low, b.q1, b.median, b.q3, b.high, b.extreme}) add(v);
  }
  if (a.zero_line && !a.log_y) add(0.0);
  if (!std::isfinite(*lo)) {
    *lo = a.log_y ? 0.1 : 0.0;
    *hi = a.log_y ? 1.0 : 1.0;
  }
}

void XRange(const Axes& a, double* lo, double* hi) {
  *lo = INFINITY;
  *hi = -INFINITY;
  for (const auto& s : a.series) {
    for (double v : s.x) {
      if (!std::isfinite(v) || (a.log_x && v <= 0.0)) continue;
      *lo = std::min(*lo, v);
      *hi = std::max(*hi, v);
    }
  }
  if (!std::isfinite(*lo)) {
    *lo = a.log_x ? 1.0 : 0.0;
    *hi = a.log_x ? 10.0 : 1.0;
  }
}

size_t MaxLength(const std::vector<std::string>& texts) {
  size_t n = 0;
  for (const auto& t : texts) n = std::max(n, t.size());
  return n;
}

struct Style {
  std::string colour;
  int shape;
  std::string dash;
  bool hollow;
};

Style StyleOf(const Series& s, int position) {
  if (s.muted) return {"#7f7f7f", 0, "5 4", true};
  const int k = s.style >= 0 ? s.style : position;
  return {kPalette[k % kColours], k % kShapes, kDashes[(k / kColours) % 3], false};
}

void Marker(std::ostream& o, double x, double y, const Style& st) {
  const std::string fill = st.hollow ? "white" : st.colour;
  const std::string paint = " fill=\"" + fill + "\" stroke=\"" + st.colour + "\" stroke-width=\"1.3\"/>\n";
  const double r = 3.6;
  switch (st.shape) {
    case 0:
      o << "<circle cx=\"" << Num(x) << "\" cy=\"" << Num(y) << "\" r=\"" << Num(r) << "\"" << paint;
      break;
    case 1:
      o << "<rect x=\"" << Num(x - r) << "\" y=\"" << Num(y - r) << "\" width=\"" << Num(2 * r) << "\" height=\""
        << Num(2 * r) << "\"" << paint;
      break;
    case 2:
      o << "<path d=\"M" << Num(x) << "," << Num(y - r * 1.2) << " L" << Num(x + r * 1.1) << "," << Num(y + r * 0.8)
        << " L" << Num(x - r * 1.1) << "," << Num(y + r * 0.8) << " Z\"" << paint;
      break;
    case 3:
      o << "<path d=\"M" << Num(x) << "," << Num(y - r * 1.3) << " L" << Num(x + r * 1.1) << "," << Num(y) << " L"
        << Num(x) << "," << Num(y + r * 1.3) << " L" << Num(x - r * 1.1) << "," << Num(y) << " Z\"" << paint;
      break;
    default:
      o << "<path d=\"M" << Num(x) << "," << Num(y + r * 1.2) << " L" << Num(x + r * 1.1) << "," << Num(y - r * 0.8)
        << " L" << Num(x - r * 1.1) << "," << Num(y - r * 0.8) << " Z\"" << paint;
  }
}

void Text(std::ostream& o, double x, double y, const std::string& text, const std::string& anchor, int size,
          const std::string& extra = "") {
  o << "<text x=\"" << Num(x) << "\" y=\"" << Num(y) << "\" text-anchor=\"" << anchor << "\" font-size=\"" << size
    << "\"" << extra << ">" << Escape(text) << "</text>\n";
}

void TickLabel(std::ostream& o, double x, double y, const Tick& t, const std::string& anchor) {
  if (!t.superscript) return Text(o, x, y, t.label, anchor, 11);
  o << "<text x=\"" << Num(x) << "\" y=\"" << Num(y) << "\" text-anchor=\"" << anchor << "\" font-size=\"11\">10"
    << "<tspan dy=\"-5\" font-size=\"8\">" << Escape(t.label) << "</tspan></text>\n";
}

// Geometry of one panel, decided before drawing so that the figure's size is known.
struct PanelLayout {
  double title_height = 0.0;
  double plot_height = kPlotHeight;
  double bottom = 0.0;  // x tick labels, x label, note
  bool rotate_categories = false;
  double Height() const { return title_height + plot_height + bottom; }
};

// Breaks a note at "; " so that each line fits `max_chars`.
std::vector<std::string> WrapNote(const std::string& note, size_t max_chars) {
  std::vector<std::string> lines;
  if (note.empty()) return lines;
  std::string current;
  size_t start = 0;
  while (start <= note.size()) {
    size_t end = note.find("; ", start);
    const std::string part = note.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string joined = current.empty() ? part : current + "; " + part;
    if (!current.empty() && joined.size() > max_chars) {
      lines.push_back(current + ";");
      current = part;
    } else {
      current = joined;
    }
    if (end == std::string::npos) break;
    start = end + 2;
  }
  lines.push_back(current);
  return lines;
}

constexpr double kNoteCharWidth = 5.6;  // of 10 px text
constexpr double kNoteLine = 14.0;

int LegendEntries(const Axes& a) {
  int n = 0;
  for (const auto& s : a.series) n += s.label.empty() ? 0 : 1;
  return n;
}

}  // namespace

std::vector<double> LinearTicks(double low, double high, int target) {
  if (!(high > low)) high = low + 1.0;
  const double raw = (high - low) / std::max(1, target - 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * magnitude;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * magnitude >= raw * (1.0 - 1e-9)) {
      step = m * magnitude;
      break;
    }
  }
  const long first = static_cast<long>(std::floor(low / step + 1e-9));
  const long last = static_cast<long>(std::ceil(high / step - 1e-9));
  std::vector<double> ticks;
  for (long k = first; k <= std::max(last, first + 1); ++k) ticks.push_back(k == 0 ? 0.0 : k * step);
  return ticks;
}

std::string FormatTick(double value, double step) {
  char buffer[48];
  if (std::abs(value) >= 1e6 || (step < 1e-4 && value != 0.0)) {
    std::snprintf(buffer, sizeof(buffer), "%.3g", value);
    return buffer;
  }
  int decimals = 0;
  for (; decimals < 10; ++decimals) {
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
  }
  if (std::abs(value) < 0.5 * step * 1e-9) value = 0.0;
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

// Grid, zero line, frame, ticks and their labels, axis labels and the panel's note.
static void DrawAxes(std::ostream& o, const Axes& a, const PanelLayout& l, const Scale& sx, const Scale& sy,
                     const std::vector<Tick>& xticks, const std::vector<Tick>& yticks, double x0, double x1, double y0,
                     double y1, double note_width) {
  // Grid, frame, ticks.
  o << "<g stroke=\"#e4e4e4\" stroke-width=\"1\">\n";
  for (const auto& t : yticks) {
    if (t.label.empty() && !a.log_y) continue;
    const double y = sy(t.value);
    if (y < y0 - 0.5 || y > y1 + 0.5) continue;
    o << "<line x1=\"" << Num(x0) << "\" y1=\"" << Num(y) << "\" x2=\"" << Num(x1) << "\" y2=\"" << Num(y) << "\""
      << (t.label.empty() ? " stroke=\"#f2f2f2\"" : "") << "/>\n";
  }
  if (a.categories.empty()) {
    for (const auto& t : xticks) {
      if (t.label.empty()) continue;
      const double x = sx(t.value);
      o << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(y0) << "\" x2=\"" << Num(x) << "\" y2=\"" << Num(y1)
        << "\"/>\n";
    }
  }
  o << "</g>\n";
  if (a.zero_line && !a.log_y && sy.lo < 0.0 && sy.hi > 0.0) {
    o << "<line x1=\"" << Num(x0) << "\" y1=\"" << Num(sy(0.0)) << "\" x2=\"" << Num(x1) << "\" y2=\"" << Num(sy(0.0))
      << "\" stroke=\"#555555\" stroke-width=\"1\"/>\n";
  }
  o << "<rect x=\"" << Num(x0) << "\" y=\"" << Num(y0) << "\" width=\"" << Num(x1 - x0) << "\" height=\""
    << Num(y1 - y0) << "\" fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>\n";
  double widest_ytick = 0.0;
  for (const auto& t : yticks) {
    const double y = sy(t.value);
    if (y < y0 - 0.5 || y > y1 + 0.5) continue;
    const double len = t.label.empty() ? 3.0 : 5.0;
    o << "<line x1=\"" << Num(x0 - len) << "\" y1=\"" << Num(y) << "\" x2=\"" << Num(x0) << "\" y2=\"" << Num(y)
      << "\" stroke=\"#333333\"/>\n";
    if (!t.label.empty()) {
      TickLabel(o, x0 - 8.0, y + 4.0, t, "end");
      widest_ytick = std::max(widest_ytick, (t.superscript ? 2 + t.label.size() * 0.7 : t.label.size()) * kCharWidth);
    }
  }
  for (const auto& t : xticks) {
    const double x = sx(t.value);
    if (x < x0 - 0.5 || x > x1 + 0.5) continue;
    const double len = t.label.empty() ? 3.0 : 5.0;
    o << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(y1) << "\" x2=\"" << Num(x) << "\" y2=\"" << Num(y1 + len)
      << "\" stroke=\"#333333\"/>\n";
    if (t.label.empty()) continue;
    if (l.rotate_categories) {
      o << "<text x=\"" << Num(x) << "\" y=\"" << Num(y1 + 14.0) << "\" text-anchor=\"end\" font-size=\"11\" "
        << "transform=\"rotate(-35 " << Num(x) << " " << Num(y1 + 14.0) << ")\">" << Escape(t.label) << "</text>\n";
    } else {
      TickLabel(o, x, y1 + 17.0, t, "middle");
    }
  }
  const double tick_labels = l.rotate_categories ? MaxLength(a.categories) * kCharWidth * 0.5 + 20.0 : 22.0;
  if (!a.x_label.empty()) Text(o, (x0 + x1) / 2, y1 + tick_labels + 18.0, a.x_label, "middle", 12);
  if (!a.y_label.empty()) {
    const double x = std::max(14.0, x0 - widest_ytick - 18.0);
    const double y = (y0 + y1) / 2;
    o << "<text x=\"" << Num(x) << "\" y=\"" << Num(y)
      << "\" text-anchor=\"middle\" font-size=\"12\" transform=\"rotate(-90 " << Num(x) << " " << Num(y) << ")\">"
      << Escape(a.y_label) << "</text>\n";
  }
  double note_y = y1 + tick_labels + (a.x_label.empty() ? 18.0 : 38.0);
  for (const auto& line : WrapNote(a.note, static_cast<size_t>(note_width / kNoteCharWidth))) {
    Text(o, x0, note_y, line, "start", 10, " fill=\"#555555\"");
    note_y += kNoteLine;
  }
}

// The panel's data, clipped to its frame: box plots, then each series' error bars, line and markers.
static void DrawData(std::ostream& o, const Axes& a, const Scale& sx, const Scale& sy, double x0, double x1, double y0,
                     double y1, size_t p) {
  // Data, clipped to the frame.
  const std::string clip = "clip" + std::to_string(p);
  o << "<clipPath id=\"" << clip << "\"><rect x=\"" << Num(x0) << "\" y=\"" << Num(y0) << "\" width=\"" << Num(x1 - x0)
    << "\" height=\"" << Num(y1 - y0) << "\"/></clipPath>\n";
  o << "<g clip-path=\"url(#" << clip << ")\">\n";
  const double box_width = std::min(40.0, 0.55 * (x1 - x0) / std::max<size_t>(1, a.categories.size()));
  for (const auto& b : a.boxes) {
    const std::string colour = kPalette[b.style % kColours];
    const double x = sx(b.position), h = box_width / 2;
    const auto Y = [&](double v) { return sy.Visible(v) ? sy(v) : sy.from; };
    o << "<g stroke=\"" << colour << "\" stroke-width=\"1.2\">\n";
    o << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(Y(b.low)) << "\" x2=\"" << Num(x) << "\" y2=\"" << Num(Y(b.q1))
      << "\"/>\n";
    o << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(Y(b.q3)) << "\" x2=\"" << Num(x) << "\" y2=\"" << Num(Y(b.high))
      << "\"/>\n";
    for (double v : {b.low, b.high}) {
      o << "<line x1=\"" << Num(x - h / 2) << "\" y1=\"" << Num(Y(v)) << "\" x2=\"" << Num(x + h / 2) << "\" y2=\""
        << Num(Y(v)) << "\"/>\n";
    }
    o << "<rect x=\"" << Num(x - h) << "\" y=\"" << Num(Y(b.q3)) << "\" width=\"" << Num(box_width) << "\" height=\""
      << Num(std::max(0.5, Y(b.q1) - Y(b.q3))) << "\" fill=\"" << colour << "\" fill-opacity=\"0.22\"/>\n";
    o << "<line x1=\"" << Num(x - h) << "\" y1=\"" << Num(Y(b.median)) << "\" x2=\"" << Num(x + h) << "\" y2=\""
      << Num(Y(b.median)) << "\" stroke-width=\"2.4\"/>\n";
    if (sy.Visible(b.extreme)) {
      o << "<circle cx=\"" << Num(x) << "\" cy=\"" << Num(sy(b.extreme)) << "\" r=\"3\" fill=\"white\"/>\n";
    }
    o << "</g>\n";
  }
  for (size_t s = 0; s < a.series.size(); ++s) {
    const Series& se = a.series[s];
    const Style st = StyleOf(se, static_cast<int>(s));
    std::vector<std::pair<double, double>> pts;
    for (size_t i = 0; i < se.x.size() && i < se.y.size(); ++i) {
      if (!sx.Visible(se.x[i]) || !sy.Visible(se.y[i])) continue;
      pts.emplace_back(sx(se.x[i]), sy(se.y[i]));
    }
    if (se.y_low.size() == se.y.size() && se.y_high.size() == se.y.size()) {
      o << "<g stroke=\"" << st.colour << "\" stroke-width=\"1.1\">\n";
      for (size_t i = 0; i < se.x.size() && i < se.y.size(); ++i) {
        if (!sx.Visible(se.x[i]) || !std::isfinite(se.y_low[i]) || !std::isfinite(se.y_high[i])) continue;
        const double lo = sy.Visible(se.y_low[i]) ? sy(se.y_low[i]) : sy.from;
        if (!sy.Visible(se.y_high[i])) continue;
        const double hi = sy(se.y_high[i]), x = sx(se.x[i]);
        o << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(lo) << "\" x2=\"" << Num(x) << "\" y2=\"" << Num(hi)
          << "\"/>\n";
        o << "<line x1=\"" << Num(x - 3) << "\" y1=\"" << Num(lo) << "\" x2=\"" << Num(x + 3) << "\" y2=\"" << Num(lo)
          << "\"/>\n";
        o << "<line x1=\"" << Num(x - 3) << "\" y1=\"" << Num(hi) << "\" x2=\"" << Num(x + 3) << "\" y2=\"" << Num(hi)
          << "\"/>\n";
      }
      o << "</g>\n";
    }
    if (se.lines && pts.size() > 1) {
      o << "<polyline fill=\"none\" stroke=\"" << st.colour << "\" stroke-width=\"1.6\""
        << (st.dash.empty() ? "" : " stroke-dasharray=\"" + st.dash + "\"") << " points=\"";
      for (size_t i = 0; i < pts.size(); ++i) o << (i ? " " : "") << Num(pts[i].first) << "," << Num(pts[i].second);
      o << "\"/>\n";
    }
    if (se.markers) {
      for (const auto& [x, y] : pts) Marker(o, x, y, st);
    }
  }
  o << "</g>\n";
}

// The legend, right of the frame.
static void DrawLegend(std::ostream& o, const Axes& a, double x1, double y0) {
  // Legend, right of the frame.
  double ly = y0 + 12.0;
  const double lx = x1 + 16.0;
  for (size_t s = 0; s < a.series.size(); ++s) {
    const Series& se = a.series[s];
    if (se.label.empty()) continue;
    const Style st = StyleOf(se, static_cast<int>(s));
    if (se.lines) {
      o << "<line x1=\"" << Num(lx) << "\" y1=\"" << Num(ly) << "\" x2=\"" << Num(lx + 24) << "\" y2=\"" << Num(ly)
        << "\" stroke=\"" << st.colour << "\" stroke-width=\"1.6\""
        << (st.dash.empty() ? "" : " stroke-dasharray=\"" + st.dash + "\"") << "/>\n";
    }
    if (se.markers) Marker(o, lx + 12, ly, st);
    Text(o, lx + 30, ly + 4, se.label, "start", 11);
    ly += 18.0;
  }
}

std::string RenderSvg(const Figure& figure) {
  // Horizontal layout, shared by every panel so that stacked panels align.
  size_t max_categories = 0, longest_category = 0, longest_legend = 0;
  bool any_legend = false;
  for (const auto& a : figure.panels) {
    max_categories = std::max(max_categories, a.categories.size());
    longest_category = std::max(longest_category, MaxLength(a.categories));
    for (const auto& s : a.series) longest_legend = std::max(longest_legend, s.label.size());
    any_legend |= LegendEntries(a) > 0;
  }
  const double slot = max_categories ? std::clamp(600.0 / max_categories, 28.0, 90.0) : 0.0;
  const double plot_width = max_categories ? std::max(420.0, slot * max_categories) : 540.0;
  const double legend_width = any_legend ? std::clamp(longest_legend * kCharWidth + 44.0, 120.0, 340.0) : 0.0;
  const double left = 96.0;
  const double width = left + plot_width + 24.0 + legend_width + 12.0;

  std::vector<PanelLayout> layouts;
  const double figure_title = figure.title.empty() ? 12.0 : 40.0;
  double height = figure_title;
  for (const auto& a : figure.panels) {
    PanelLayout l;
    l.title_height = a.title.empty() ? 10.0 : 28.0;
    l.plot_height = std::max(kPlotHeight, 18.0 * LegendEntries(a) + 16.0);
    l.rotate_categories = !a.categories.empty() && MaxLength(a.categories) * kCharWidth > slot - 6.0;
    const double tick_labels = l.rotate_categories ? MaxLength(a.categories) * kCharWidth * 0.5 + 20.0 : 22.0;
    const size_t note_chars = static_cast<size_t>((plot_width + legend_width) / kNoteCharWidth);
    l.bottom = tick_labels + (a.x_label.empty() ? 6.0 : 26.0) + 10.0 + kNoteLine * WrapNote(a.note, note_chars).size();
    layouts.push_back(l);
    height += l.Height();
  }
  height += 8.0;

  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << Num(width) << "\" height=\"" << Num(height)
    << "\" viewBox=\"0 0 " << Num(width) << " " << Num(height)
    << "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" fill=\"#222222\">\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << Num(width) << "\" height=\"" << Num(height) << "\" fill=\"white\"/>\n";
  if (!figure.title.empty()) Text(o, width / 2, 26.0, figure.title, "middle", 16, " font-weight=\"bold\"");

  double top = figure_title;
  for (size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& a = figure.panels[p];
    const PanelLayout& l = layouts[p];
    const double x0 = left, x1 = left + plot_width;
    const double y0 = top + l.title_height, y1 = y0 + l.plot_height;
    if (!a.title.empty()) Text(o, (x0 + x1) / 2, top + 19.0, a.title, "middle", 13, " font-weight=\"bold\"");

    // Scales and ticks.
    Scale sx, sy;
    sx.from = x0;
    sx.to = x1;
    sy.from = y1;
    sy.to = y0;
    std::vector<Tick> xticks;
    if (!a.categories.empty()) {
      sx.lo = -0.5;
      sx.hi = static_cast<double>(a.categories.size()) - 0.5;
      for (size_t i = 0; i < a.categories.size(); ++i)
        xticks.push_back({static_cast<double>(i), a.categories[i], false});
    } else {
      double lo, hi;
      XRange(a, &lo, &hi);
      xticks = AxisTicks(lo, hi, a.log_x, &sx);
    }
    double ylo, yhi;
    YRange(a, &ylo, &yhi);
    const std::vector<Tick> yticks = AxisTicks(ylo, yhi, a.log_y, &sy);

    DrawAxes(o, a, l, sx, sy, xticks, yticks, x0, x1, y0, y1, plot_width + legend_width);
    DrawData(o, a, sx, sy, x0, x1, y0, y1, p);
    DrawLegend(o, a, x1, y0);
    top += l.Height();
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace kincal::svg
