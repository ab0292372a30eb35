#pragma once
// The files a study writes into its output folder. The report is generated from these files only, so a
// merge of shards (kincal merge) and an unsharded run give the same report.
//
//   study.json       what was run (StudyManifest) and which shard this folder holds ("shard": "i/N")
//   results.csv      one row per (work item, compensator, validation set): error distributions and status.
//                    Deterministic: the same study gives the same bytes, whatever the threads or shards.
//   timings.csv      the same keys with identify_seconds and compensate_seconds_per_target (not
//                    deterministic, hence apart)
//   parameters.csv   one row per (work item, parameter): nominal, estimate, stddev, truth, error
//   convergence.csv  compensator convergence per iteration (the study's first random validation set)
//   iso9283.csv      ISO 9283 AP and RP per pose P1..P5
//   heldout.csv      measured data: every held-out row's error with its reach and approach speed (the
//                    report's error-against-reach and error-against-speed plots), its predicted standard
//                    deviation sd_mm and whether it lies outside what the training poses support
//   selection.csv    estimators with `select: true`: every candidate's CV RMS, se, parameters, chosen
// Every row starts with the work item's index; rows are in item order.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "studies/evaluation.h"

namespace kincal {

// A CSV table held as text cells (kincal's CSVs have no quoting; text cells never hold commas).
struct ResultTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int Column(const std::string& name) const;  // -1 if absent
  // Cell as a number; NaN when empty or not a number.
  double Number(size_t row, int column) const;
  const std::string& Text(size_t row, int column) const;
};

std::string TableToCsv(const ResultTable& table);
// How the tables write numbers: %.<digits>g, "" for NaN.
std::string FormatResultNumber(double value, int digits = 6);
// Throws std::invalid_argument naming the file when it is missing or malformed.
ResultTable ReadResultTable(const std::string& path);

// The result tables of a set of work items, in item order.
struct StudyTables {
  ResultTable results, timings, parameters, convergence, iso9283, heldout, selection;
  static constexpr int kCount = 7;
  // The tables in the order of kStudyTableFiles.
  std::array<ResultTable*, kCount> All() {
    return {&results, &timings, &parameters, &convergence, &iso9283, &heldout, &selection};
  }
  std::array<const ResultTable*, kCount> All() const {
    return {&results, &timings, &parameters, &convergence, &iso9283, &heldout, &selection};
  }
};
inline const char* const kStudyTableFiles[StudyTables::kCount] = {
    "results.csv", "timings.csv", "parameters.csv", "convergence.csv", "iso9283.csv", "heldout.csv", "selection.csv"};

StudyTables MakeStudyTables(const Study& study, const std::vector<DatasetVariant>& variants,
                            const std::vector<ItemResult>& results);

// A model that predicts its held-out rows worse than geometry alone on the same data (the row of the
// estimator named `geometry`, same dataset, variant and trial) by more than kWorseThanGeometry is not
// blessed: its heldout row's status `ok` becomes `heldout_worse_than_geometry`, with the ratio in its note.
// Run on a whole study's results (unsharded, or merged), where the geometry row is at hand.
inline constexpr const char* kGeometryEstimator = "geometry";
inline constexpr double kWorseThanGeometry = 1.5;
void FlagWorseThanGeometry(ResultTable* results);

// Writes study.json (the manifest plus "shard") and the tables into `dir` (created if needed).
void WriteStudyFiles(const std::string& dir, const nlohmann::json& manifest, const std::string& shard,
                     const StudyTables& tables);

// Reads the tables of a results folder.
StudyTables ReadStudyTables(const std::string& dir);
nlohmann::json ReadManifest(const std::string& dir);

// Combines shard folders (`kincal study --shard i/N`) into `out`: checks that they come from the same study
// and together hold every work item exactly once, then writes the files an unsharded run writes.
// Throws std::invalid_argument on any mismatch. Does not write the report (see WriteReport).
void MergeShards(const std::vector<std::string>& dirs, const std::string& out);

}  // namespace kincal
