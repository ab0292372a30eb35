#pragma once
// The result files of a study folder, indexed for the report: rows grouped by (dataset variant, estimator,
// compensator, validation set), statistics over Monte Carlo trials, the study's order of everything.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "studies/results_files.h"

namespace kincal {

// Values of one quantity over trials (NaNs left out).
struct TrialValues {
  std::vector<double> values;
  void Add(double v);
  int count() const { return static_cast<int>(values.size()); }
  double Mean() const;    // NaN if empty
  double Stddev() const;  // sample standard deviation; NaN with fewer than 2 values
};

class ReportData {
 public:
  // Throws std::invalid_argument when a file is missing or malformed.
  explicit ReportData(const std::string& dir);

  struct Variant {
    std::string dataset;
    std::string label;      // "sweep" or "sweep[noise=10um]"
    std::string knob;       // "" when the dataset sweeps nothing
    std::string knob_text;  // knob_value as the tables write it
    double knob_value = 0.0;
    bool simulated = true;
    bool iso9283 = false;  // measured data scored by ISO 9283 too (validation "iso9283")
  };

  const std::string& dir() const { return dir_; }
  const nlohmann::json& manifest() const { return manifest_; }
  const StudyTables& tables() const { return tables_; }
  const std::vector<Variant>& variants() const { return variants_; }
  std::vector<std::string> Estimators() const;              // study order, "none" first
  std::vector<std::string> Compensators() const;            // "-" (prediction) first, then "none", then the study's
  std::vector<std::string> Validations(int variant) const;  // "heldout" for measured data
  bool IsIso(const std::string& validation) const;
  int trials() const { return manifest_.value("trials", 1); }

  // Row indices of a table for one group, in trial order.
  std::vector<size_t> Rows(const ResultTable& table, int variant, const std::string& estimator,
                           const std::string& compensator, const std::string& validation) const;
  // A column of results.csv over the trials of a group.
  TrialValues Values(int variant, const std::string& estimator, const std::string& compensator,
                     const std::string& validation, const std::string& column) const;
  // Variant index of a row of any table (its dataset and knob_value columns).
  int VariantOf(const ResultTable& table, size_t row) const;

 private:
  std::string dir_;
  nlohmann::json manifest_;
  StudyTables tables_;
  std::vector<Variant> variants_;
  std::map<std::string, int> variant_index_;
  mutable std::map<const ResultTable*, std::map<std::string, std::vector<size_t>>> groups_;
};

// One parameter over estimators and trials (report units: mm, deg, or none for ratios).
struct ParameterSummary {
  std::string name, unit;
  double nominal = 0.0;
  double truth = 0.0;                         // NaN for measured data
  std::map<std::string, TrialValues> error;   // per estimator: estimate - truth (- nominal without a truth)
  std::map<std::string, TrialValues> stddev;  // per estimator: the standard deviation it reported
  // Per estimator, from error-model fits with priors (studies/parameter_rows.h); absent where none.
  struct Trust {
    TrialValues prior_sd, data_sd, data_share;
    int weak = 0;                // trials in which the parameter was weak
    std::string trades_against;  // a weak parameter's partners (the first trial's that names them)
  };
  std::map<std::string, Trust> trust;
};
// Parameters that the truth or some estimator moved away from the nominal, in the tables' order.
std::vector<ParameterSummary> SummarizeParameters(const ReportData& data, int variant);

// Number text for the report: 3 decimals from 0.01 up, 2 significant digits below.
std::string ReportNumber(double v);
// "mean ± std" (the ± part only with a finite spread).
std::string MeanSpread(const TrialValues& v, double scale = 1.0);
// A file-name-safe version of a label.
std::string Slug(const std::string& text);

}  // namespace kincal
