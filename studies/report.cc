#include "studies/report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "framework/atomic_file.h"
#include "studies/report_data.h"
#include "studies/report_plots.h"

namespace kincal {
namespace {

std::string Cell(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out.empty() ? "–" : out;
}

void Row(std::ostream& o, const std::vector<std::string>& cells) {
  o << "|";
  for (const auto& c : cells) o << " " << c << " |";
  o << "\n";
}

void Header(std::ostream& o, const std::vector<std::string>& cells, const std::vector<bool>& right = {}) {
  Row(o, cells);
  o << "|";
  for (size_t i = 0; i < cells.size(); ++i) o << (i < right.size() && right[i] ? "---:|" : "---|");
  o << "\n";
}

std::string Code(const std::string& text) { return text.empty() ? "defaults" : "`" + Cell(text) + "`"; }

std::string Statuses(const ReportData& data, int variant, const MethodPair& p, const std::string& validation) {
  const ResultTable& t = data.tables().results;
  std::map<std::string, int> counts;
  for (size_t r : data.Rows(t, variant, p.estimator, p.compensator, validation))
    ++counts[t.Text(r, t.Column("status"))];
  std::string out;
  for (const auto& [status, n] : counts) {
    out += (out.empty() ? "" : ", ") + (counts.size() == 1 && status == "ok" ? "ok" : std::to_string(n) + " " + status);
  }
  return out;
}

std::string Improvement(double before, double after) {
  if (!std::isfinite(before) || !std::isfinite(after) || before <= 0) return "–";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f %%", 100.0 * (1.0 - after / before));
  return buffer;
}

void WhatWasRun(std::ostream& o, const ReportData& data) {
  const auto& m = data.manifest();
  o << "## What was run\n\n";
  Header(o, {"", ""});
  Row(o, {"seed", std::to_string(m.value("seed", 0ULL))});
  Row(o, {"Monte Carlo trials", std::to_string(data.trials())});
  Row(o, {"work items (dataset x trial x estimator)", std::to_string(m.value("items", 0))});
  const auto& robots = m.at("robots");
  Row(o, {"nominal robot (the controller's)", Cell(robots.at("nominal").at("name").get<std::string>()) + " (" +
                                                  Cell(robots.at("nominal").at("source").get<std::string>()) + ")"});
  if (robots.contains("truth")) {
    Row(o, {"truth (the simulated arm)", Cell(robots.at("truth").at("name").get<std::string>()) + " (" +
                                             Cell(robots.at("truth").at("source").get<std::string>()) + ")"});
  }
  o << "\n**Datasets**\n\n";
  Header(o, {"dataset", "what", "swept knob"});
  for (const auto& d : m.at("datasets")) {
    std::string vary = "–";
    if (d.contains("vary")) {
      vary = d.at("vary").at("knob").get<std::string>() + ": ";
      for (const auto& v : d.at("vary").at("values")) vary += v.get<std::string>() + " ";
    }
    Row(o, {Cell(d.at("name").get<std::string>()), Cell(d.at("summary").get<std::string>()), Cell(vary)});
  }
  o << "\n**Estimators** (each a pipeline: every stage starts from the robot the one before identified)\n\n";
  Header(o, {"estimator", "pipeline", "options", "datasets"});
  for (const auto& e : m.at("estimators")) {
    std::string methods, options, datasets;
    const auto& names = e.at("methods");
    for (size_t i = 0; i < names.size(); ++i) {
      methods += (i ? " → " : "") + names[i].get<std::string>();
      const std::string text = e.at("options")[i].get<std::string>();
      if (!text.empty()) options += (options.empty() ? "" : "; ") + names[i].get<std::string>() + ": " + text;
    }
    for (const auto& d : e.at("datasets")) datasets += (datasets.empty() ? "" : ", ") + d.get<std::string>();
    Row(o, {Cell(e.at("name").get<std::string>()), Cell(methods), Code(options),
            datasets.empty() ? "all" : Cell(datasets)});
  }
  o << "\n**Compensators**\n\n";
  Header(o, {"compensator", "method", "options"});
  for (const auto& c : m.at("compensators")) {
    Row(o, {Cell(c.at("name").get<std::string>()), Cell(c.at("method").get<std::string>()),
            Code(c.at("options").get<std::string>())});
  }
  if (!m.at("validation").empty()) {
    o << "\n**Validation sets**\n\n";
    Header(o, {"validation", "targets"});
    for (const auto& v : m.at("validation")) {
      Row(o, {Cell(v.at("name").get<std::string>()), Cell(v.at("summary").get<std::string>())});
    }
  }
  o << "\nHow to read the tables. A target is a tool pose; the controller commands its nominal joint solution "
       "through its nominal reduction ratios, and the simulated arm (the truth) turns by what the motor counts mean "
       "with its real ratios. **before** is that nominal command as is (estimator `none`, compensator `none`); "
       "**estimator / compensator** is what the compensator commands for the identified robot; **estimator (model)** "
       "is the identified robot's own prediction error of where the arm goes, with no compensation (it scores the "
       "estimator alone). Errors are exact distances between the target and the true arm's tool pose. Each trial "
       "gives a mean, RMS and maximum over the targets; the tables show their mean ± standard deviation over the "
       "trials. Measured datasets are scored by prediction on their held-out test rows; there **before** is the "
       "nominal geometry with only the base and the tool or markers fitted to the training rows. Pairs with `none` "
       "on one side only reproduce **before** and are in results.csv. A status other than `ok` says what went "
       "wrong: `estimate_at_bounds` means the estimator ended with parameters on their bounds.\n\n";
}

void ErrorTable(std::ostream& o, const ReportData& data, int variant, const std::string& validation) {
  const std::vector<MethodPair> pairs = MethodPairs(data, variant, validation);
  if (pairs.empty()) return;
  const auto value = [&](const MethodPair& p, const std::string& column) {
    return data.Values(variant, p.estimator, p.compensator, validation, column);
  };
  const MethodPair* before = nullptr;
  for (const auto& p : pairs) {
    if (p.label == "before") before = &p;
  }
  Header(o,
         {"method", "position mean (mm)", "position RMS (mm)", "position max (mm)", "orientation mean (deg)",
          "orientation max (deg)", "position vs before", "orientation vs before", "status"},
         {false, true, true, true, true, true, true, true, false});
  std::vector<std::string> notes;
  for (const auto& p : pairs) {
    const TrialValues pm = value(p, "position_error_mean_mm"), om = value(p, "orientation_error_mean_deg");
    std::string pi = "–", oi = "–";
    if (before && &p != before) {
      pi = Improvement(value(*before, "position_error_mean_mm").Mean(), pm.Mean());
      oi = Improvement(value(*before, "orientation_error_mean_deg").Mean(), om.Mean());
    }
    const std::string label = p.label == "before" ? "**before**" : Cell(p.label);
    Row(o, {label, MeanSpread(pm), MeanSpread(value(p, "position_error_rms_mm")),
            MeanSpread(value(p, "position_error_max_mm")), MeanSpread(om),
            MeanSpread(value(p, "orientation_error_max_deg")), pi, oi, Cell(Statuses(data, variant, p, validation))});
    const ResultTable& t = data.tables().results;
    std::set<std::string> seen;
    for (size_t r : data.Rows(t, variant, p.estimator, p.compensator, validation)) {
      const std::string& note = t.Text(r, t.Column("note"));
      if (t.Text(r, t.Column("status")) != "ok" && !note.empty() && seen.insert(note).second && seen.size() <= 2) {
        notes.push_back(p.label + ": " + note);
      }
    }
  }
  o << "\n";
  for (const auto& n : notes) o << "- " << Cell(n) << "\n";
  if (!notes.empty()) o << "\n";
}

void IsoTable(std::ostream& o, const ReportData& data, int variant, const std::string& validation) {
  const ResultTable& t = data.tables().iso9283;
  const std::vector<MethodPair> pairs = MethodPairs(data, variant, validation);
  o << "ISO 9283 pose accuracy AP and repeatability RP at the poses P1, P2, ... (the largest over them; mean ± std "
       "over "
       "trials). AP_P: distance from the commanded position to the mean attained one; RP_l = mean distance to "
       "the barycentre + 3 S_l; orientation: largest of the a, b, c components.\n\n";
  Header(o, {"method", "AP_P (mm)", "RP_l (mm)", "AP orientation (deg)", "RP orientation (deg)"},
         {false, true, true, true, true});
  const int c_item = t.Column("item");
  for (const auto& p : pairs) {
    std::map<std::string, std::array<double, 4>> per_trial;
    for (size_t r : data.Rows(t, variant, p.estimator, p.compensator, validation)) {
      auto& worst = per_trial.try_emplace(t.Text(r, c_item), std::array<double, 4>{0, 0, 0, 0}).first->second;
      worst[0] = std::max(worst[0], t.Number(r, t.Column("AP_P_mm")));
      worst[1] = std::max(worst[1], t.Number(r, t.Column("RP_l_mm")));
      for (const char* c : {"AP_a_deg", "AP_b_deg", "AP_c_deg"})
        worst[2] = std::max(worst[2], std::abs(t.Number(r, t.Column(c))));
      for (const char* c : {"RP_a_deg", "RP_b_deg", "RP_c_deg"})
        worst[3] = std::max(worst[3], t.Number(r, t.Column(c)));
    }
    if (per_trial.empty()) continue;
    TrialValues v[4];
    for (const auto& kv : per_trial) {
      for (int k = 0; k < 4; ++k) v[k].Add(kv.second[k]);
    }
    Row(o, {p.label == "before" ? "**before**" : Cell(p.label), MeanSpread(v[0]), MeanSpread(v[1]), MeanSpread(v[2]),
            MeanSpread(v[3])});
  }
  o << "\n";
}

// What the priors did (error-model fits with `prior: on`, studies/parameter_rows.h): per parameter and
// estimator that gave it a prior or found it weak, the prior's sd, the posterior's, the data's alone and
// the data's share of the information (1 - posterior^2 / prior^2). A share near 0 means the prior, not the
// data, placed the parameter: not a calibration result to trust.
void ParameterTrustTable(std::ostream& o, const std::vector<ParameterSummary>& params,
                         const std::vector<std::string>& estimators) {
  bool any = false;
  for (const auto& p : params) {
    for (const auto& e : estimators) any |= p.trust.count(e) > 0;
  }
  if (!any) return;
  o << "Priors and weak parameters: standard deviations in the parameter's unit, means over trials; "
       "posterior: with the prior (the sd in brackets above), data: from the data alone; data share = 1 − "
       "posterior² / prior²; weak: in how many trials the data alone could not determine it, and what it "
       "trades against.\n\n";
  Header(o, {"parameter", "unit", "estimator", "prior sd", "posterior sd", "data sd", "data share", "weak"},
         {false, false, false, true, true, true, true, false});
  for (const auto& p : params) {
    for (const auto& e : estimators) {
      const auto t = p.trust.find(e);
      if (t == p.trust.end()) continue;
      const ParameterSummary::Trust& trust = t->second;
      const auto mean = [](const TrialValues& v) { return v.count() ? ReportNumber(v.Mean()) : std::string("–"); };
      const auto sd = p.stddev.find(e);
      const int trials = p.error.count(e) ? p.error.at(e).count() : 0;
      std::string weak = "–";
      if (trust.weak > 0) {
        weak = std::to_string(trust.weak) + "/" + std::to_string(trials) + " trials";
        if (!trust.trades_against.empty()) weak += ", trades against " + trust.trades_against;
      }
      Row(o, {Cell(p.name), p.unit.empty() ? "–" : p.unit, Cell(e), mean(trust.prior_sd),
              sd == p.stddev.end() ? "–" : mean(sd->second), mean(trust.data_sd), mean(trust.data_share), weak});
    }
  }
  o << "\n";
}

void ParameterTable(std::ostream& o, const ReportData& data, int variant) {
  const std::vector<ParameterSummary> params = SummarizeParameters(data, variant);
  if (params.empty()) {
    o << "No estimator changed a parameter.\n\n";
    return;
  }
  const bool truth = std::isfinite(params.front().truth);
  std::vector<std::string> estimators;  // those with parameters (not failed everywhere), but the baseline
  for (const auto& e : data.Estimators()) {
    bool any = false;
    for (const auto& p : params) any |= p.error.count(e) && p.error.at(e).count() > 0;
    if (e != "none" && any) estimators.push_back(e);
  }
  o << (truth
            ? "Identified minus true value, mean ± standard deviation over trials; in brackets the standard deviation "
              "the estimator reported (mean over trials). "
            : "Identified minus nominal value (measured data: no truth), mean ± standard deviation over trials; in "
              "brackets the reported standard deviation. ")
    << "Lengths in mm, angles in deg, ratios dimensionless; joint-error coefficients in deg, deg/mm or s (deg per "
       "deg/s).\n\n";
  std::vector<std::string> header = {"parameter", "unit"};
  if (truth) header.push_back("nominal − truth");
  for (const auto& e : estimators) header.push_back(Cell(e));
  std::vector<bool> right(header.size(), true);
  right[0] = right[1] = false;
  Header(o, header, right);
  std::map<std::string, std::map<std::string, std::vector<double>>> squares;  // estimator -> unit -> errors^2
  for (const auto& p : params) {
    std::vector<std::string> cells = {Cell(p.name), p.unit.empty() ? "–" : p.unit};
    if (truth) cells.push_back(ReportNumber(p.nominal - p.truth));
    for (const auto& e : estimators) {
      const auto err = p.error.find(e);
      if (err == p.error.end() || err->second.count() == 0) {
        cells.push_back("–");
        continue;
      }
      std::string cell = MeanSpread(err->second);
      const auto sd = p.stddev.find(e);
      if (sd != p.stddev.end() && sd->second.count()) cell += " (" + ReportNumber(sd->second.Mean()) + ")";
      cells.push_back(cell);
      squares[e][p.unit].push_back(err->second.Mean() * err->second.Mean());
    }
    Row(o, cells);
  }
  o << "\nRMS over the parameters above (of the mean errors):\n\n";
  Header(o, {"estimator", "lengths (mm)", "angles (deg)", "ratios"}, {false, true, true, true});
  const auto rms = [](const std::vector<double>& v) {
    if (v.empty()) return std::string("–");
    double s = 0.0;
    for (double x : v) s += x;
    return ReportNumber(std::sqrt(s / v.size()));
  };
  if (truth) {
    std::map<std::string, std::vector<double>> before;
    for (const auto& p : params) before[p.unit].push_back((p.nominal - p.truth) * (p.nominal - p.truth));
    Row(o, {"nominal (before)", rms(before["mm"]), rms(before["deg"]), rms(before[""])});
  }
  for (const auto& e : estimators) {
    Row(o, {Cell(e), rms(squares[e]["mm"]), rms(squares[e]["deg"]), rms(squares[e][""])});
  }
  o << "\n";
  ParameterTrustTable(o, params, estimators);
}

void SensitivityTable(std::ostream& o, const ReportData& data, const std::string& dataset,
                      const std::string& validation) {
  std::vector<int> variants;
  for (size_t v = 0; v < data.variants().size(); ++v) {
    if (data.variants()[v].dataset == dataset) variants.push_back(static_cast<int>(v));
  }
  const std::vector<MethodPair> pairs = MethodPairs(data, variants.front(), validation);
  o << "Mean position error (mm) at the targets of " << Cell(validation) << ", against "
    << KnobLabel(data.variants()[variants.front()].knob) << " (mean ± std over trials).\n\n";
  std::vector<std::string> header = {"method"};
  for (int v : data.variants().empty() ? std::vector<int>() : variants) header.push_back(data.variants()[v].knob_text);
  std::vector<bool> right(header.size(), true);
  right[0] = false;
  Header(o, header, right);
  for (const auto& p : pairs) {
    std::vector<std::string> cells = {p.label == "before" ? "**before**" : Cell(p.label)};
    for (int v : variants)
      cells.push_back(MeanSpread(data.Values(v, p.estimator, p.compensator, validation, "position_error_mean_mm")));
    Row(o, cells);
  }
  o << "\n";
}

// Instruments side by side: the simulated datasets that sweep a knob, grouped by the instrument they
// simulate (study.json), one table per instrument and random validation set with a row per value of every
// knob its datasets sweep (the number of measurements in one, the noise in another) and a column per
// method. Written when the study compares instruments or sweeps two knobs of one.
void InstrumentTables(std::ostream& o, const ReportData& data) {
  std::vector<std::string> instruments;
  std::map<std::string, std::vector<int>> variants;  // instrument -> its swept datasets' variants
  std::set<std::string> datasets;
  for (const auto& d : data.manifest().at("datasets")) {
    if (!d.contains("instrument") || !d.contains("vary")) continue;
    const std::string instrument = d.at("instrument").get<std::string>();
    if (!variants.count(instrument)) instruments.push_back(instrument);
    datasets.insert(d.at("name").get<std::string>());
    for (size_t v = 0; v < data.variants().size(); ++v) {
      if (data.variants()[v].dataset == d.at("name").get<std::string>()) variants[instrument].push_back(v);
    }
  }
  if (instruments.size() < 2 && datasets.size() < 2) return;
  o << "## Instruments side by side\n\n";
  for (const auto& validation_spec : data.manifest().at("validation")) {
    if (validation_spec.at("kind") != "random") continue;
    const std::string validation = validation_spec.at("name").get<std::string>();
    for (const std::string& instrument : instruments) {
      const std::vector<int>& vs = variants[instrument];
      const std::vector<MethodPair> pairs = MethodPairs(data, vs.front(), validation);
      o << "### " << Cell(instrument) << ": " << Cell(validation) << "\n\nMean position error (mm) at the targets "
        << "of " << Cell(validation) << " (mean ± std over trials) against each knob the " << Cell(instrument)
        << " datasets sweep.\n\n";
      std::vector<std::string> header = {"dataset", "knob", "value"};
      for (const auto& p : pairs) header.push_back(p.label == "before" ? "**before**" : Cell(p.label));
      std::vector<bool> right(header.size(), true);
      right[0] = right[1] = false;
      Header(o, header, right);
      for (int v : vs) {
        const ReportData::Variant& var = data.variants()[v];
        std::vector<std::string> cells = {Cell(var.dataset), KnobLabel(var.knob), var.knob_text};
        for (const auto& p : pairs)
          cells.push_back(MeanSpread(data.Values(v, p.estimator, p.compensator, validation, "position_error_mean_mm")));
        Row(o, cells);
      }
      o << "\n";
    }
  }
}

void Times(std::ostream& o, const ReportData& data) {
  const ResultTable& t = data.tables().timings;
  const int c_item = t.Column("item"), c_est = t.Column("estimator"), c_comp = t.Column("compensator");
  std::map<std::string, TrialValues> identify, compensate;
  std::set<std::string> items;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (items.insert(t.Text(r, c_item)).second)
      identify[t.Text(r, c_est)].Add(t.Number(r, t.Column("identify_seconds")));
    if (t.Text(r, c_comp) != "-")
      compensate[t.Text(r, c_comp)].Add(t.Number(r, t.Column("compensate_seconds_per_target")));
  }
  o << "## Times\n\nWall-clock times on the machine that ran each work item (timings.csv; not part of the "
       "deterministic results). Mean ± standard deviation over runs.\n\n";
  Header(o, {"estimator", "identification (s)", "runs"}, {false, true, true});
  for (const auto& e : data.Estimators()) {
    if (identify.count(e)) Row(o, {Cell(e), MeanSpread(identify[e]), std::to_string(identify[e].count())});
  }
  o << "\n";
  Header(o, {"compensator", "per target (ms)", "validation runs"}, {false, true, true});
  for (const auto& c : data.Compensators()) {
    if (compensate.count(c)) Row(o, {Cell(c), MeanSpread(compensate[c], 1e3), std::to_string(compensate[c].count())});
  }
  o << "\n";
}

void Figure(std::ostream& o, const std::string& path, const std::string& caption) {
  if (!path.empty()) o << "![" << caption << "](" << path << ")\n\n";
}

// The model selection tables of a measured or simulated variant (selection.csv), one per estimator and trial.
void SelectionTables(std::ostream& o, const ReportData& data, int variant) {
  const ResultTable& t = data.tables().selection;
  if (t.rows.empty()) return;
  const int c_est = t.Column("estimator"), c_trial = t.Column("trial"), c_cand = t.Column("candidate");
  std::string current;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (data.VariantOf(t, r) != variant) continue;
    const std::string group = t.Text(r, c_est) + ", trial " + t.Text(r, c_trial);
    if (group != current) {
      if (current.empty())
        o << "### Model selection (blocked cross-validation, paired one-standard-error rule)\n\n";
      else
        o << "\n";
      current = group;
      o << "Estimator " << Cell(group)
        << ":\n\n| candidate | parameters | CV RMS ± se (mm) | chosen |\n|---|---|---|---|\n";
    }
    o << "| " << Cell(t.Text(r, c_cand)) << " | " << t.Text(r, t.Column("parameters")) << " | "
      << ReportNumber(t.Number(r, t.Column("cv_rms_mm"))) << " ± " << ReportNumber(t.Number(r, t.Column("se_mm")))
      << " | " << (t.Text(r, t.Column("chosen")) == "1" ? "**chosen**" : "") << " |\n";
  }
  if (!current.empty()) o << "\n";
}

// Per estimator: the held-out rows' median predicted sd and how many lie outside the training support.
void UncertaintyTable(std::ostream& o, const ReportData& data, int variant) {
  const ResultTable& t = data.tables().heldout;
  const int c_sd = t.Column("sd_mm"), c_out = t.Column("outside_support"), c_est = t.Column("estimator");
  const int c_tau = t.Column("tau_mm");  // absent in results written before it was
  if (c_sd < 0) return;
  std::map<std::string, std::vector<double>> sd;
  std::map<std::string, double> tau;  // the largest over the rows
  std::map<std::string, int> outside;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (data.VariantOf(t, r) != variant || !std::isfinite(t.Number(r, c_sd))) continue;
    sd[t.Text(r, c_est)].push_back(t.Number(r, c_sd));
    outside[t.Text(r, c_est)] += t.Text(r, c_out) == "1" ? 1 : 0;
    const double row_tau = c_tau >= 0 ? t.Number(r, c_tau) : NAN;
    if (std::isfinite(row_tau)) tau[t.Text(r, c_est)] = std::max(tau[t.Text(r, c_est)], row_tau);
  }
  if (sd.empty()) return;
  o << "### Prediction uncertainty of the held-out rows\n\n"
       "sd: the predicted position standard deviation, sqrt(trace(J C J^T) + tau^2); tau: the model's "
       "inadequacy measured by cross-validation (`select` or `cross_validate`; 0 without: the sd is then the "
       "parameters' part only); outside: rows whose parameters' sd exceeds 3 x the median over the training rows "
       "or with a joint beyond the training range (where not to trust the model).\n\n"
       "| estimator | median sd (mm) | max sd (mm) | max tau (mm) | outside / rows |\n|---|---|---|---|---|\n";
  for (const auto& e : data.Estimators()) {
    auto it = sd.find(e);
    if (it == sd.end()) continue;
    std::vector<double> v = it->second;
    std::sort(v.begin(), v.end());
    const auto t_it = tau.find(e);
    o << "| " << Cell(e) << " | " << ReportNumber(v[v.size() / 2]) << " | " << ReportNumber(v.back()) << " | "
      << (t_it == tau.end() ? std::string("-") : ReportNumber(t_it->second)) << " | " << outside[e] << " / "
      << v.size() << " |\n";
  }
  o << "\n";
}

}  // namespace

void WriteReport(const std::string& dir) {
  const ReportData data(dir);
  const auto& m = data.manifest();
  std::ostringstream o;
  o << "# Study: " << m.value("name", "") << "\n\n";
  if (!m.value("description", "").empty()) o << m.value("description", "") << "\n\n";
  WhatWasRun(o, data);

  std::set<std::string> swept;
  for (int v = 0; v < static_cast<int>(data.variants().size()); ++v) {
    const ReportData::Variant& var = data.variants()[v];
    if (!var.knob.empty()) {
      swept.insert(var.dataset);
      continue;
    }
    o << "## Dataset " << Cell(var.label) << "\n\n";
    for (const auto& validation : data.Validations(v)) {
      if (data.IsIso(validation)) {
        o << "### ISO 9283: " << Cell(validation) << "\n\n";
        if (!var.simulated) {
          o << "Measured: the test rows' poses visited at least twice, numbered P1, P2, ... by first visit; the "
               "commanded pose in the instrument's frame is where each model puts it (studies/measured_iso9283.h), "
               "so AP is the accuracy left after compensating with that model and RP is the arm's own.\n\n";
        }
        IsoTable(o, data, v, validation);
        o << (var.simulated ? "Errors at P1..P5 themselves (no noise):\n\n"
                            : "Prediction errors at every visit of those poses:\n\n");
      } else {
        o << "### Validation " << Cell(validation) << "\n\n";
      }
      ErrorTable(o, data, v, validation);
      if (!data.IsIso(validation))
        Figure(o, PlotErrorDistributions(data, v, validation), "error distributions, " + var.label + ", " + validation);
    }
    if (!var.simulated) {
      const std::string heldout = PlotHeldoutAgainst(data, v);
      if (!heldout.empty()) {
        o << "### Held-out error against reach and approach speed\n\n";
        Figure(o, heldout, "held-out error against reach and approach speed, " + var.label);
      }
    }
    SelectionTables(o, data, v);
    if (!var.simulated) UncertaintyTable(o, data, v);
    o << "### Parameters\n\n";
    ParameterTable(o, data, v);
    Figure(o, PlotParameterErrors(data, v), "parameter errors, " + var.label);
    const std::string convergence = PlotConvergence(data, v);
    if (!convergence.empty()) {
      o << "### Compensator convergence\n\n";
      Figure(o, convergence, "compensator convergence, " + var.label);
    }
  }
  for (const auto& d : m.at("datasets")) {
    const std::string dataset = d.at("name").get<std::string>();
    if (!swept.count(dataset)) continue;
    o << "## Sensitivity: " << Cell(dataset) << "\n\n";
    for (const auto& v : m.at("validation")) {
      if (v.at("kind") != "random") continue;
      const std::string validation = v.at("name").get<std::string>();
      SensitivityTable(o, data, dataset, validation);
      Figure(o, PlotSensitivity(data, dataset, validation), "sensitivity, " + dataset + ", " + validation);
    }
  }
  InstrumentTables(o, data);
  Times(o, data);
  o << "## Files\n\n"
       "- `results.csv`: one row per (work item, compensator, validation set): error distribution over the targets "
       "(mean, RMS, max, 5/25/50/75/95 % quantiles), status\n"
       "- `parameters.csv`: every identified parameter with its nominal, estimate, reported standard deviation, "
       "truth and error; with priors, the prior's sd, the data's alone, the data's share and the weak flag with "
       "the parameters it trades against\n"
       "- `heldout.csv` (measured data): every held-out row's error with its reach and approach speed, its "
       "predicted sd and whether it lies outside the training support\n"
       "- `selection.csv`: the model selection of estimators with `select: true`\n"
       "- `convergence.csv`, `iso9283.csv`, `timings.csv`; `study.json`: what was run\n";
  WriteFileAtomically(dir + "/report.md", o.str());
}

}  // namespace kincal
