#include "studies/report_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "framework/error.h"

namespace kincal {

void TrialValues::Add(double v) {
  if (std::isfinite(v)) values.push_back(v);
}

double TrialValues::Mean() const {
  if (values.empty()) return NAN;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / values.size();
}

double TrialValues::Stddev() const {
  if (values.size() < 2) return NAN;
  const double mean = Mean();
  double sum = 0.0;
  for (double v : values) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / (values.size() - 1));
}

std::string ReportNumber(double v) {
  if (!std::isfinite(v)) return "–";
  char buffer[48];
  if (v == 0.0) return "0";
  if (std::abs(v) >= 1000.0)
    std::snprintf(buffer, sizeof(buffer), "%.0f", v);
  else if (std::abs(v) >= 0.01)
    std::snprintf(buffer, sizeof(buffer), "%.3f", v);
  else
    std::snprintf(buffer, sizeof(buffer), "%.2g", v);
  return buffer;
}

std::string MeanSpread(const TrialValues& v, double scale) {
  if (v.count() == 0) return "–";
  std::string s = ReportNumber(v.Mean() * scale);
  double sd = v.Stddev();
  if (sd <= 1e-9 * std::abs(v.Mean())) sd = 0.0;  // identical trials up to round-off
  if (std::isfinite(sd)) s += " ± " + ReportNumber(sd * scale);
  return s;
}

std::string Slug(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
    if (keep)
      out += c;
    else if (!out.empty() && out.back() != '_')
      out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out.empty() ? "x" : out;
}

ReportData::ReportData(const std::string& dir) : dir_(dir) {
  manifest_ = ReadManifest(dir);
  if (manifest_.value("shard", "1/1") != "1/1") {
    ThrowInputError(dir + ": holds shard " + manifest_.value("shard", "") +
                    " of a study; combine the shards with kincal merge");
  }
  tables_ = ReadStudyTables(dir);
  std::map<std::string, bool> simulated, iso;
  for (const auto& d : manifest_.at("datasets")) {
    simulated[d.at("name").get<std::string>()] = d.at("simulated").get<bool>();
    iso[d.at("name").get<std::string>()] = d.value("iso9283", false);
  }
  for (const auto& v : manifest_.at("variants")) {
    Variant x;
    x.dataset = v.at("dataset").get<std::string>();
    x.label = v.at("label").get<std::string>();
    x.knob = v.at("knob").get<std::string>();
    if (!v.at("knob_value").is_null()) {
      x.knob_value = v.at("knob_value").get<double>();
      x.knob_text = FormatResultNumber(x.knob_value);
    }
    x.simulated = simulated[x.dataset];
    x.iso9283 = iso[x.dataset];
    variant_index_[x.dataset + "|" + x.knob_text] = static_cast<int>(variants_.size());
    variants_.push_back(x);
  }
}

std::vector<std::string> ReportData::Estimators() const {
  std::vector<std::string> out;
  for (const auto& e : manifest_.at("estimators")) out.push_back(e.at("name").get<std::string>());
  return out;
}

std::vector<std::string> ReportData::Compensators() const {
  std::vector<std::string> out = {"-"};
  for (const auto& c : manifest_.at("compensators")) out.push_back(c.at("name").get<std::string>());
  return out;
}

std::vector<std::string> ReportData::Validations(int variant) const {
  if (!variants_[variant].simulated) {
    if (variants_[variant].iso9283) return {"heldout", "iso9283"};
    return {"heldout"};
  }
  std::vector<std::string> out;
  for (const auto& v : manifest_.at("validation")) out.push_back(v.at("name").get<std::string>());
  return out;
}

bool ReportData::IsIso(const std::string& validation) const {
  for (const auto& v : manifest_.at("validation")) {
    if (v.at("name") == validation) return v.at("kind") == "iso9283";
  }
  if (validation == "iso9283") return true;  // measured data's ISO 9283 rows
  return false;
}

int ReportData::VariantOf(const ResultTable& table, size_t row) const {
  const std::string key = table.Text(row, table.Column("dataset")) + "|" + table.Text(row, table.Column("knob_value"));
  const auto it = variant_index_.find(key);
  return it == variant_index_.end() ? -1 : it->second;
}

std::vector<size_t> ReportData::Rows(const ResultTable& table, int variant, const std::string& estimator,
                                     const std::string& compensator, const std::string& validation) const {
  auto& groups = groups_[&table];
  if (groups.empty()) {
    const int e = table.Column("estimator"), c = table.Column("compensator"), v = table.Column("validation");
    for (size_t r = 0; r < table.rows.size(); ++r) {
      groups[std::to_string(VariantOf(table, r)) + "|" + table.Text(r, e) + "|" + table.Text(r, c) + "|" +
             table.Text(r, v)]
          .push_back(r);
    }
    groups["#built"];
  }
  const auto it = groups.find(std::to_string(variant) + "|" + estimator + "|" + compensator + "|" + validation);
  return it == groups.end() ? std::vector<size_t>() : it->second;
}

TrialValues ReportData::Values(int variant, const std::string& estimator, const std::string& compensator,
                               const std::string& validation, const std::string& column) const {
  TrialValues out;
  const int col = tables_.results.Column(column);
  for (size_t r : Rows(tables_.results, variant, estimator, compensator, validation)) {
    out.Add(tables_.results.Number(r, col));
  }
  return out;
}

std::vector<ParameterSummary> SummarizeParameters(const ReportData& data, int variant) {
  const ResultTable& t = data.tables().parameters;
  const int c_name = t.Column("parameter"), c_unit = t.Column("unit"), c_nominal = t.Column("nominal"),
            c_estimate = t.Column("estimate"), c_stddev = t.Column("stddev"), c_truth = t.Column("truth"),
            c_prior_sd = t.Column("prior_sd"), c_data_sd = t.Column("data_sd"), c_share = t.Column("data_share"),
            c_weak = t.Column("weak"), c_partners = t.Column("trades_against");
  std::vector<ParameterSummary> all;
  std::map<std::string, size_t> index;
  std::map<std::string, bool> moved;
  for (const std::string& estimator : data.Estimators()) {
    for (size_t r : data.Rows(t, variant, estimator, "", "")) {
      const std::string& name = t.Text(r, c_name);
      if (!index.count(name)) {
        index[name] = all.size();
        ParameterSummary p;
        p.name = name;
        p.unit = t.Text(r, c_unit);
        p.nominal = t.Number(r, c_nominal);
        p.truth = t.Number(r, c_truth);
        all.push_back(p);
        const double scale = std::max(1.0, std::abs(p.nominal));
        moved[name] = std::isfinite(p.truth) && std::abs(p.truth - p.nominal) > 1e-9 * scale;
      }
      ParameterSummary& p = all[index[name]];
      const double estimate = t.Number(r, c_estimate);
      p.error[estimator].Add(estimate - (std::isfinite(p.truth) ? p.truth : p.nominal));
      p.stddev[estimator].Add(t.Number(r, c_stddev));
      const bool weak = t.Text(r, c_weak) == "1";
      if (std::isfinite(t.Number(r, c_prior_sd)) || weak) {
        ParameterSummary::Trust& trust = p.trust[estimator];
        trust.prior_sd.Add(t.Number(r, c_prior_sd));
        trust.data_sd.Add(t.Number(r, c_data_sd));
        trust.data_share.Add(t.Number(r, c_share));
        trust.weak += weak ? 1 : 0;
        if (trust.trades_against.empty()) trust.trades_against = t.Text(r, c_partners);
      }
      if (std::abs(estimate - p.nominal) > 1e-9 * std::max(1.0, std::abs(p.nominal))) moved[name] = true;
    }
  }
  std::vector<ParameterSummary> out;
  for (const auto& p : all) {
    if (moved[p.name]) out.push_back(p);
  }
  return out;
}

}  // namespace kincal
