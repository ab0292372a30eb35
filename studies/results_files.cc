#include "studies/results_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "framework/atomic_file.h"
#include "framework/csv.h"
#include "framework/error.h"
#include "framework/units.h"

namespace kincal {
namespace {

// Text cells: commas would split the cell, line breaks the row.
std::string Clean(std::string text) {
  for (char& c : text) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (text.size() > 240) text = text.substr(0, 237) + "...";
  return text;
}

std::string Format(double value, int digits = 6) { return FormatResultNumber(value, digits); }

const std::vector<std::string> kKey = {"item",  "dataset",   "knob",        "knob_value",
                                       "trial", "estimator", "compensator", "validation"};

std::vector<std::string> Key(const Study& study, const std::vector<DatasetVariant>& variants, const ItemResult& r,
                             const EvaluationRow* row) {
  const DatasetVariant& v = variants[r.item.variant];
  std::vector<std::string> key = {
      std::to_string(r.item.index), study.datasets[v.dataset].name, v.knob,
      Format(v.knob_value),         std::to_string(r.item.trial),   study.pipelines[r.item.pipeline].name};
  if (row) {
    key.push_back(row->compensator);
    key.push_back(row->validation);
  }
  return key;
}

std::vector<std::string> Concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

void AddSummary(std::vector<std::string>* cells, const ErrorSummary& s, double scale) {
  for (double v : {s.mean, s.rms, s.max, s.p05, s.p25, s.median, s.p75, s.p95}) cells->push_back(Format(v * scale));
}

std::vector<std::string> SummaryColumns(const std::string& prefix, const std::string& unit) {
  std::vector<std::string> out;
  for (const char* stat : {"mean", "rms", "max", "p05", "p25", "p50", "p75", "p95"}) {
    out.push_back(prefix + "_" + stat + "_" + unit);
  }
  return out;
}

int ItemOf(const ResultTable& t, size_t row, const std::string& source) {
  double v = t.Number(row, 0);
  if (!std::isfinite(v) || v < 0 || v != std::floor(v))
    ThrowInputError(source + ": bad item index '" + t.Text(row, 0) + "'");
  return static_cast<int>(v);
}

}  // namespace

std::string FormatResultNumber(double value, int digits) {
  if (!std::isfinite(value)) return "";
  char buffer[48];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
  return buffer;
}

int ResultTable::Column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  return -1;
}

double ResultTable::Number(size_t row, int column) const {
  double v = NAN;
  if (column < 0 || !ParseDouble(rows[row][column], &v)) return NAN;
  return v;
}

const std::string& ResultTable::Text(size_t row, int column) const {
  static const std::string empty;
  return column < 0 ? empty : rows[row][column];
}

std::string TableToCsv(const ResultTable& table) {
  std::string out;
  const auto line = [&](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + cells[i];
    out += "\n";
  };
  line(table.header);
  for (const auto& row : table.rows) line(row);
  return out;
}

ResultTable ReadResultTable(const std::string& path) {
  const CsvTable csv = ParseCsv(ReadFileToString(path), path);
  ResultTable t;
  t.header = csv.header.cells;
  for (const auto& row : csv.rows) t.rows.push_back(row.cells);
  return t;
}

StudyTables MakeStudyTables(const Study& study, const std::vector<DatasetVariant>& variants,
                            const std::vector<ItemResult>& results) {
  StudyTables t;
  t.results.header = Concat(kKey, {"targets", "converged"});
  t.results.header = Concat(t.results.header, SummaryColumns("position_error", "mm"));
  t.results.header = Concat(t.results.header, SummaryColumns("orientation_error", "deg"));
  t.results.header = Concat(t.results.header, {"estimation_status", "status", "note"});
  t.timings.header = Concat(kKey, {"identify_seconds", "compensate_seconds_per_target"});
  t.parameters.header = {"item",      "dataset",  "knob",    "knob_value", "trial",  "estimator",
                         "parameter", "unit",     "nominal", "estimate",   "stddev", "truth",
                         "error",     "prior_sd", "data_sd", "data_share", "weak",   "trades_against"};
  t.convergence.header = Concat(kKey, {"iteration", "position_error_median_mm", "position_error_max_mm",
                                       "orientation_error_median_deg", "orientation_error_max_deg", "active_targets"});
  t.heldout.header = {"item",      "dataset", "knob",           "knob_value", "trial",
                      "estimator", "row",     "marker",         "reach_mm",   "approach_speed_deg_s",
                      "error_mm",  "sd_mm",   "outside_support", "tau_mm"};
  t.selection.header = {"item",      "dataset",    "knob",      "knob_value", "trial", "estimator",
                        "candidate", "parameters", "cv_rms_mm", "se_mm",      "chosen"};
  t.iso9283.header = Concat(kKey, {"pose", "cycles", "AP_P_mm", "AP_a_deg", "AP_b_deg", "AP_c_deg", "RP_l_mm",
                                   "RP_a_deg", "RP_b_deg", "RP_c_deg"});
  const double mm = 1e3, deg = 180.0 / M_PI;
  std::vector<const ItemResult*> ordered;
  for (const auto& r : results) ordered.push_back(&r);
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const ItemResult* a, const ItemResult* b) { return a->item.index < b->item.index; });
  for (const ItemResult* r : ordered) {
    for (const EvaluationRow& row : r->rows) {
      const std::vector<std::string> key = Key(study, variants, *r, &row);
      std::vector<std::string> cells = Concat(key, {std::to_string(row.targets), std::to_string(row.converged)});
      AddSummary(&cells, row.position, mm);
      AddSummary(&cells, row.orientation, deg);
      cells.push_back(r->estimation_status);
      cells.push_back(row.status);
      cells.push_back(Clean(row.note));
      t.results.rows.push_back(cells);
      t.timings.rows.push_back(Concat(key, {Format(r->identify_seconds), Format(row.compensate_seconds_per_target)}));
      for (const ConvergencePoint& c : row.convergence) {
        t.convergence.rows.push_back(Concat(key, {std::to_string(c.iteration), Format(c.position_median * mm),
                                                  Format(c.position_max * mm), Format(c.orientation_median * deg),
                                                  Format(c.orientation_max * deg), std::to_string(c.active_targets)}));
      }
      for (const IsoPoseResult& p : row.iso) {
        const Iso9283PoseStats& s = p.stats;
        t.iso9283.rows.push_back(Concat(
            key, {"P" + std::to_string(p.pose), std::to_string(s.cycles), Format(s.ap_p * mm),
                  Format(s.ap_abc[0] * deg), Format(s.ap_abc[1] * deg), Format(s.ap_abc[2] * deg), Format(s.rp_l * mm),
                  Format(s.rp_abc[0] * deg), Format(s.rp_abc[1] * deg), Format(s.rp_abc[2] * deg)}));
      }
    }
    for (const HeldoutPoint& h : r->heldout) {
      t.heldout.rows.push_back(
          Concat(Key(study, variants, *r, nullptr),
                 {std::to_string(h.row), h.marker, Format(h.reach * mm), Format(h.approach_speed * deg),
                  Format(h.error * mm), Format(h.sd * mm), h.outside_support ? "1" : "0", Format(h.tau * mm)}));
    }
    for (const SelectionRow& c : r->selection) {
      t.selection.rows.push_back(Concat(
          Key(study, variants, *r, nullptr),
          {c.candidate, std::to_string(c.parameters), Format(c.cv_rms * mm), Format(c.se * mm), c.chosen ? "1" : "0"}));
    }
    for (const ParameterRow& p : r->parameters) {
      t.parameters.rows.push_back(
          Concat(Key(study, variants, *r, nullptr),
                 {p.name, p.unit, Format(p.nominal, 10), Format(p.estimate, 10), Format(p.stddev, 4),
                  Format(p.truth, 10), Format(p.estimate - p.truth, 6), Format(p.prior_sd, 4), Format(p.data_sd, 4),
                  Format(p.data_share, 4), p.weak ? "1" : "0", p.trades_against}));
    }
  }
  return t;
}

void FlagWorseThanGeometry(ResultTable* results) {
  const ResultTable& t = *results;
  const int dataset = t.Column("dataset"), knob = t.Column("knob"), value = t.Column("knob_value"),
            trial = t.Column("trial"), estimator = t.Column("estimator"), compensator = t.Column("compensator"),
            validation = t.Column("validation"), rms = t.Column("position_error_rms_mm"), status = t.Column("status"),
            note = t.Column("note");
  if (std::min({dataset, knob, value, trial, estimator, compensator, validation, rms, status, note}) < 0) return;
  // The model's own held-out rows (compensator "-"), keyed by the data they were scored on.
  const auto key = [&](size_t r) {
    return t.Text(r, dataset) + "\x1f" + t.Text(r, knob) + "\x1f" + t.Text(r, value) + "\x1f" + t.Text(r, trial);
  };
  const auto heldout = [&](size_t r) { return t.Text(r, compensator) == "-" && t.Text(r, validation) == "heldout"; };
  std::map<std::string, double> geometry;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (heldout(r) && t.Text(r, estimator) == kGeometryEstimator) geometry[key(r)] = t.Number(r, rms);
  }
  for (size_t r = 0; r < t.rows.size(); ++r) {
    // The baseline `none` is the nominal geometry, registered: worse than geometry by design.
    if (!heldout(r) || t.Text(r, status) != "ok" || t.Text(r, estimator) == "none") continue;
    const auto it = geometry.find(key(r));
    if (it == geometry.end() || !(it->second > 0.0)) continue;
    const double ratio = t.Number(r, rms) / it->second;
    if (!(ratio > kWorseThanGeometry)) continue;
    results->rows[r][status] = "heldout_worse_than_geometry";
    const std::string why = "held-out RMS " + FormatResultNumber(ratio, 3) + " x the geometry row's (" +
                            FormatResultNumber(it->second, 4) + " mm)";
    std::string& cell = results->rows[r][note];
    cell = cell.empty() ? why : cell + "; " + why;
  }
}

void WriteStudyFiles(const std::string& dir, const nlohmann::json& manifest, const std::string& shard,
                     const StudyTables& tables) {
  std::filesystem::create_directories(dir);
  nlohmann::json m = manifest;
  m["shard"] = shard;
  WriteFileAtomically(dir + "/study.json", m.dump(2) + "\n");
  const auto all = tables.All();
  for (int i = 0; i < StudyTables::kCount; ++i)
    WriteFileAtomically(dir + "/" + kStudyTableFiles[i], TableToCsv(*all[i]));
}

nlohmann::json ReadManifest(const std::string& dir) {
  const std::string path = dir + "/study.json";
  try {
    return nlohmann::json::parse(ReadFileToString(path));
  } catch (const nlohmann::json::exception& e) {
    ThrowInputError(path + ": not a study manifest (" + e.what() + ")");
  }
}

StudyTables ReadStudyTables(const std::string& dir) {
  StudyTables t;
  const auto all = t.All();
  for (int i = 0; i < StudyTables::kCount; ++i) *all[i] = ReadResultTable(dir + "/" + kStudyTableFiles[i]);
  return t;
}

void MergeShards(const std::vector<std::string>& dirs, const std::string& out) {
  if (dirs.empty()) ThrowInputError("merge: no result folders given");
  nlohmann::json reference;
  std::set<int> shards;
  int count = 0;
  for (size_t i = 0; i < dirs.size(); ++i) {
    nlohmann::json m = ReadManifest(dirs[i]);
    const std::string shard = m.value("shard", "");
    int index = 0, n = 0;
    if (std::sscanf(shard.c_str(), "%d/%d", &index, &n) != 2 || index < 1 || index > n) {
      ThrowInputError(dirs[i] + "/study.json: bad shard '" + shard + "'");
    }
    m.erase("shard");
    if (i == 0) {
      reference = m;
      count = n;
    } else if (m != reference) {
      ThrowInputError("merge: " + dirs[i] + " holds results of a different study than " + dirs[0]);
    } else if (n != count) {
      ThrowInputError("merge: " + dirs[i] + " is a shard of " + std::to_string(n) + ", " + dirs[0] + " of " +
                      std::to_string(count));
    }
    if (!shards.insert(index).second) ThrowInputError("merge: shard " + shard + " given twice (" + dirs[i] + ")");
  }
  if (static_cast<int>(shards.size()) != count) {
    ThrowInputError("merge: " + std::to_string(shards.size()) + " of " + std::to_string(count) + " shards given");
  }

  StudyTables merged;
  std::vector<std::pair<int, std::vector<std::string>>> keyed[StudyTables::kCount];
  std::set<int> items;
  for (const auto& dir : dirs) {
    const StudyTables t = ReadStudyTables(dir);
    const auto in = t.All();
    const auto to = merged.All();
    for (int f = 0; f < StudyTables::kCount; ++f) {
      const std::string source = dir + "/" + kStudyTableFiles[f];
      if (to[f]->header.empty()) to[f]->header = in[f]->header;
      if (in[f]->header != to[f]->header) ThrowInputError("merge: " + source + " has different columns");
      std::set<int> here;
      for (size_t r = 0; r < in[f]->rows.size(); ++r) {
        const int item = ItemOf(*in[f], r, source);
        keyed[f].emplace_back(item, in[f]->rows[r]);
        if (f == 0) here.insert(item);
      }
      for (int item : here) {
        if (!items.insert(item).second)
          ThrowInputError("merge: work item " + std::to_string(item) + " is in two shards");
      }
    }
  }
  const int num_items = reference.value("items", 0);
  if (static_cast<int>(items.size()) != num_items) {
    ThrowInputError("merge: the shards hold " + std::to_string(items.size()) + " of the study's " +
                    std::to_string(num_items) + " work items");
  }
  const auto to = merged.All();
  for (int f = 0; f < StudyTables::kCount; ++f) {
    std::stable_sort(keyed[f].begin(), keyed[f].end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& kv : keyed[f]) to[f]->rows.push_back(std::move(kv.second));
  }
  FlagWorseThanGeometry(&merged.results);
  WriteStudyFiles(out, reference, "1/1", merged);
}

}  // namespace kincal
