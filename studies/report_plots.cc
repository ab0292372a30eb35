#include "studies/report_plots.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "framework/atomic_file.h"
#include "studies/svg_plot.h"

namespace kincal {
namespace {

std::string Write(const ReportData& data, const std::string& name, const svg::Figure& figure) {
  std::filesystem::create_directories(data.dir() + "/plots");
  const std::string relative = "plots/" + name + ".svg";
  WriteFileAtomically(data.dir() + "/" + relative, svg::RenderSvg(figure));
  return relative;
}

int EstimatorStyle(const ReportData& data, const std::string& estimator) {
  const std::vector<std::string> all = data.Estimators();
  const auto it = std::find(all.begin(), all.end(), estimator);
  // "none" (index 0) takes black, the last colour; the others the palette in order.
  const int i = static_cast<int>(it - all.begin());
  return i == 0 ? 7 : i - 1;
}

// Log scale when the positive values span more than two decades.
bool WideRange(const std::vector<double>& values) {
  double lo = INFINITY, hi = 0.0;
  for (double v : values) {
    if (std::isfinite(v) && v > 0) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return std::isfinite(lo) && hi / lo > 100.0;
}

std::string Trials(const ReportData& data) {
  const int n = data.trials();
  return std::to_string(n) + (n == 1 ? " trial" : " trials");
}

}  // namespace

std::string KnobLabel(const std::string& knob) {
  if (knob == "noise_um") return "position noise σ per axis (µm)";
  if (knob == "noise_range_um_per_m") return "range-dependent noise (µm per m)";
  if (knob == "poses") return "random poses";
  if (knob == "stops") return "stops per joint";
  if (knob == "step_deg") return "step between stops (deg)";
  if (knob == "arc_deg") return "sweep arc per joint (deg)";
  return knob;
}

std::vector<MethodPair> MethodPairs(const ReportData& data, int variant, const std::string& validation) {
  std::vector<MethodPair> out;
  const auto add = [&](const std::string& e, const std::string& c, const std::string& label) {
    if (data.Rows(data.tables().results, variant, e, c, validation).empty()) return;
    out.push_back({e, c, label, EstimatorStyle(data, e)});
  };
  if (!data.variants()[variant].simulated) {
    for (const auto& e : data.Estimators()) add(e, "-", e == "none" ? "nominal" : e);
    return out;
  }
  add("none", "none", "before");
  for (const auto& e : data.Estimators()) {
    if (e == "none") continue;
    add(e, "-", e + " (model)");
    for (const auto& c : data.Compensators()) {
      if (c != "-" && c != "none") add(e, c, e + " / " + c);
    }
  }
  return out;
}

std::string PlotErrorDistributions(const ReportData& data, int variant, const std::string& validation) {
  const std::vector<MethodPair> pairs = MethodPairs(data, variant, validation);
  if (pairs.empty()) return "";
  const std::string what[2] = {"position_error", "orientation_error"};
  const std::string unit[2] = {"mm", "deg"};
  svg::Figure figure;
  figure.title = "Error distributions: " + data.variants()[variant].label + ", " + validation;
  for (int k = 0; k < 2; ++k) {
    svg::Axes axes;
    axes.title = k == 0 ? "Position error at the targets" : "Orientation error at the targets";
    axes.y_label = (k == 0 ? "position error (" : "orientation error (") + unit[k] + ")";
    axes.note =
        "box: 25-75 %; bar: median; whiskers: 5-95 %; circle: largest error; quantiles averaged over " + Trials(data);
    std::vector<double> all;
    bool zero = false;
    for (size_t i = 0; i < pairs.size(); ++i) {
      const auto q = [&](const char* stat) {
        return data.Values(variant, pairs[i].estimator, pairs[i].compensator, validation,
                           what[k] + "_" + stat + "_" + unit[k]);
      };
      svg::Box box;
      box.position = static_cast<double>(axes.categories.size());
      box.low = q("p05").Mean();
      box.q1 = q("p25").Mean();
      box.median = q("p50").Mean();
      box.q3 = q("p75").Mean();
      box.high = q("p95").Mean();
      const TrialValues max = q("max");
      box.extreme = max.count() ? *std::max_element(max.values.begin(), max.values.end()) : NAN;
      box.style = pairs[i].style;
      if (!std::isfinite(box.median)) continue;  // failed in every trial: see the table's status
      axes.categories.push_back(pairs[i].label);
      for (double v : {box.low, box.high, box.extreme}) all.push_back(v);
      zero |= box.low <= 0.0;
      axes.boxes.push_back(box);
    }
    if (axes.boxes.empty()) continue;
    axes.log_y = WideRange(all);
    if (axes.log_y && zero) axes.note += "; errors of 0 on the bottom edge";
    figure.panels.push_back(axes);
  }
  if (figure.panels.empty()) return "";
  return Write(data, "errors_" + Slug(data.variants()[variant].label) + "_" + Slug(validation), figure);
}

std::string PlotParameterErrors(const ReportData& data, int variant) {
  const std::vector<ParameterSummary> params = SummarizeParameters(data, variant);
  if (params.empty()) return "";
  const bool truth = std::isfinite(params.front().truth);
  std::vector<std::string> estimators;
  for (const auto& e : data.Estimators()) {
    if (e != "none") estimators.push_back(e);
  }
  svg::Figure figure;
  figure.title =
      std::string(truth ? "Parameter errors (identified - truth): " : "Parameter changes (identified - nominal): ") +
      data.variants()[variant].label;
  const std::pair<std::string, std::string> groups[3] = {
      {"mm", "length parameters"}, {"deg", "angle parameters"}, {"", "reduction ratios"}};
  for (const auto& [unit, title] : groups) {
    std::vector<const ParameterSummary*> mine;
    for (const auto& p : params) {
      if (p.unit == unit) mine.push_back(&p);
    }
    if (mine.empty()) continue;
    svg::Axes axes;
    axes.title = title;
    axes.y_label = std::string(truth ? "error" : "change") + (unit.empty() ? "" : " (" + unit + ")");
    axes.zero_line = true;
    axes.note = "points: mean over " + Trials(data) +
                "; bars: ±1 σ reported by the estimator (the spread over trials when it reports none)" +
                (truth ? "; grey: nominal - truth" : "");
    for (const auto* p : mine) axes.categories.push_back(p->name);
    const size_t count = estimators.size() + (truth ? 1 : 0);
    const double width = std::min(0.7, 0.18 * count);
    const auto offset = [&](size_t s) { return count < 2 ? 0.0 : -width / 2 + width * s / (count - 1); };
    if (truth) {
      svg::Series before;
      before.label = "nominal (before)";
      before.muted = true;
      before.lines = false;
      for (size_t i = 0; i < mine.size(); ++i) {
        before.x.push_back(i + offset(0));
        before.y.push_back(mine[i]->nominal - mine[i]->truth);
      }
      axes.series.push_back(before);
    }
    for (size_t s = 0; s < estimators.size(); ++s) {
      svg::Series series;
      series.label = estimators[s];
      series.lines = false;
      series.style = EstimatorStyle(data, estimators[s]);
      for (size_t i = 0; i < mine.size(); ++i) {
        const auto e = mine[i]->error.find(estimators[s]);
        if (e == mine[i]->error.end() || e->second.count() == 0) continue;
        const auto sd = mine[i]->stddev.find(estimators[s]);
        double bar = sd != mine[i]->stddev.end() ? sd->second.Mean() : NAN;
        if (!std::isfinite(bar)) bar = e->second.Stddev();
        const double mean = e->second.Mean();
        series.x.push_back(i + offset(s + (truth ? 1 : 0)));
        series.y.push_back(mean);
        series.y_low.push_back(std::isfinite(bar) ? mean - bar : NAN);
        series.y_high.push_back(std::isfinite(bar) ? mean + bar : NAN);
      }
      if (!series.x.empty()) axes.series.push_back(series);
    }
    figure.panels.push_back(axes);
  }
  return Write(data, "parameters_" + Slug(data.variants()[variant].label), figure);
}

std::string PlotConvergence(const ReportData& data, int variant) {
  const ResultTable& t = data.tables().convergence;
  if (t.rows.empty()) return "";
  const int c_iteration = t.Column("iteration");
  svg::Figure figure;
  figure.title = "Compensator convergence: " + data.variants()[variant].label;
  const std::string columns[2] = {"position_error_median_mm", "orientation_error_median_deg"};
  bool any = false;
  for (int k = 0; k < 2; ++k) {
    svg::Axes axes;
    axes.title = k == 0 ? "Position error (median over targets)" : "Orientation error (median over targets)";
    axes.x_label = "iteration";
    axes.y_label = k == 0 ? "position error (mm)" : "orientation error (deg)";
    axes.log_y = true;
    axes.note = "errors against the identified model, as the compensator sees them; mean over " + Trials(data) +
                "; zero drawn at 1e-12";
    const int column = t.Column(columns[k]);
    const std::vector<std::string> compensators = data.Compensators();
    for (const auto& e : data.Estimators()) {
      if (e == "none") continue;
      for (size_t ci = 2; ci < compensators.size(); ++ci) {  // after "-" and "none"
        const std::string& c = compensators[ci];
        std::map<int, TrialValues> by_iteration;
        for (const auto& v : data.Validations(variant)) {
          for (size_t r : data.Rows(t, variant, e, c, v)) {
            by_iteration[static_cast<int>(t.Number(r, c_iteration))].Add(t.Number(r, column));
          }
        }
        if (by_iteration.empty()) continue;
        svg::Series s;
        s.label = e + " / " + c;
        // One colour per estimator, one dash and marker per compensator.
        s.style = EstimatorStyle(data, e) + 8 * static_cast<int>(ci - 2);
        for (const auto& [iteration, values] : by_iteration) {
          if (values.count() == 0) continue;
          s.x.push_back(iteration);
          s.y.push_back(std::max(values.Mean(), 1e-12));
        }
        if (s.x.empty()) continue;
        axes.series.push_back(s);
      }
    }
    if (axes.series.empty()) continue;
    any = true;
    figure.panels.push_back(axes);
  }
  if (!any) return "";
  return Write(data, "convergence_" + Slug(data.variants()[variant].label), figure);
}

std::string PlotSensitivity(const ReportData& data, const std::string& dataset, const std::string& validation) {
  std::vector<int> variants;
  for (size_t v = 0; v < data.variants().size(); ++v) {
    if (data.variants()[v].dataset == dataset && !data.variants()[v].knob.empty())
      variants.push_back(static_cast<int>(v));
  }
  if (variants.empty()) return "";
  const std::string knob = data.variants()[variants.front()].knob;
  const std::vector<MethodPair> pairs = MethodPairs(data, variants.front(), validation);
  svg::Figure figure;
  figure.title = "Sensitivity: " + dataset + ", " + validation;
  const std::string columns[2] = {"position_error_mean_mm", "orientation_error_mean_deg"};
  std::vector<double> xs;
  for (int v : variants) xs.push_back(data.variants()[v].knob_value);
  const double lo = *std::min_element(xs.begin(), xs.end()), hi = *std::max_element(xs.begin(), xs.end());
  for (int k = 0; k < 2; ++k) {
    svg::Axes axes;
    axes.title = k == 0 ? "Mean position error at the targets" : "Mean orientation error at the targets";
    axes.x_label = KnobLabel(knob);
    axes.y_label = k == 0 ? "position error (mm)" : "orientation error (deg)";
    axes.log_x = lo > 0 && hi / lo > 20.0;
    axes.note = "mean over " + Trials(data) + "; bars: ±1 standard deviation over trials";
    std::vector<double> all;
    for (size_t p = 0; p < pairs.size(); ++p) {
      svg::Series s;
      s.label = pairs[p].label;
      s.muted = pairs[p].label == "before";
      s.style = static_cast<int>(p);
      for (int v : variants) {
        const TrialValues values = data.Values(v, pairs[p].estimator, pairs[p].compensator, validation, columns[k]);
        if (values.count() == 0) continue;
        const double mean = values.Mean(), sd = values.Stddev();
        s.x.push_back(data.variants()[v].knob_value);
        s.y.push_back(mean);
        s.y_low.push_back(std::isfinite(sd) ? mean - sd : NAN);
        s.y_high.push_back(std::isfinite(sd) ? mean + sd : NAN);
        all.push_back(mean);
      }
      if (!s.x.empty()) axes.series.push_back(s);
    }
    if (axes.series.empty()) continue;
    axes.log_y = WideRange(all);
    figure.panels.push_back(axes);
  }
  if (figure.panels.empty()) return "";
  return Write(data, "sensitivity_" + Slug(dataset) + "_" + Slug(validation), figure);
}

std::string PlotHeldoutAgainst(const ReportData& data, int variant) {
  const ResultTable& t = data.tables().heldout;
  const int estimator_col = t.Column("estimator"), error_col = t.Column("error_mm");
  if (t.rows.empty() || estimator_col < 0 || error_col < 0) return "";
  struct Quantity {
    const char* column;
    const char* title;
    const char* label;
  };
  const Quantity quantities[2] = {
      {"reach_mm", "Held-out RMS error against reach", "horizontal distance from axis 1 (mm)"},
      {"approach_speed_deg_s", "Held-out RMS error against approach speed",
       "fastest joint's speed on the way to the pose (deg/s)"}};
  std::vector<size_t> rows;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (data.VariantOf(t, r) == variant) rows.push_back(r);
  }
  if (rows.empty()) return "";
  svg::Figure figure;
  figure.title = "Held-out error: " + data.variants()[variant].label;
  constexpr int kBins = 8;
  for (const Quantity& q : quantities) {
    const int x_col = t.Column(q.column);
    if (x_col < 0) continue;
    // Bin edges at quantiles of the x values, so that every bin holds about as many rows.
    std::vector<double> xs;
    for (size_t r : rows) {
      if (std::isfinite(t.Number(r, x_col))) xs.push_back(t.Number(r, x_col));
    }
    if (xs.size() < 2 * kBins) continue;
    std::sort(xs.begin(), xs.end());
    std::vector<double> edges;
    for (int b = 0; b <= kBins; ++b) edges.push_back(xs[std::min(xs.size() - 1, b * (xs.size() - 1) / kBins)]);
    svg::Axes axes;
    axes.title = q.title;
    axes.x_label = q.label;
    axes.y_label = "held-out RMS position error (mm)";
    axes.note = "RMS over the test rows of each bin (bins hold equal numbers of rows), all trials pooled";
    for (const std::string& estimator : data.Estimators()) {
      std::vector<double> sum2(kBins, 0.0), sum_x(kBins, 0.0);
      std::vector<int> count(kBins, 0);
      for (size_t r : rows) {
        if (t.Text(r, estimator_col) != estimator) continue;
        const double x = t.Number(r, x_col), e = t.Number(r, error_col);
        if (!std::isfinite(x) || !std::isfinite(e)) continue;
        const int b = std::min<int>(
            kBins - 1, static_cast<int>(std::upper_bound(edges.begin() + 1, edges.end() - 1, x) - (edges.begin() + 1)));
        sum2[b] += e * e;
        sum_x[b] += x;
        ++count[b];
      }
      svg::Series s;
      s.label = estimator == "none" ? "before" : estimator;
      s.muted = estimator == "none";
      s.style = EstimatorStyle(data, estimator);
      for (int b = 0; b < kBins; ++b) {
        if (count[b] == 0) continue;
        s.x.push_back(sum_x[b] / count[b]);
        s.y.push_back(std::sqrt(sum2[b] / count[b]));
      }
      if (!s.x.empty()) axes.series.push_back(s);
    }
    if (!axes.series.empty()) figure.panels.push_back(axes);
  }
  if (figure.panels.empty()) return "";
  return Write(data, "heldout_" + Slug(data.variants()[variant].label), figure);
}

}  // namespace kincal
