#pragma once
// report.md and its plots, generated from a results folder's files alone (study.json and the tables), so
// that `kincal merge` of shards and an unsharded run report alike.
#include <string>

namespace kincal {

// Writes DIR/report.md and DIR/plots/*.svg. Throws std::invalid_argument when a file is missing or is a
// shard (merge shards first).
void WriteReport(const std::string& dir);

}  // namespace kincal
