#pragma once
// Minimal CSV reading with positions for error messages: comma separated, no quoting (kincal's files
// hold numbers and short identifiers only), '#' comment lines, blank lines skipped.
#include <string>
#include <vector>

namespace kincal {

struct CsvRow {
  int line = 0;  // 1-based line in the file
  std::vector<std::string> cells;
  std::vector<int> columns;  // 1-based column of each cell's first character
};

struct CsvTable {
  std::vector<std::string> comments;  // without the leading '#'
  CsvRow header;
  std::vector<CsvRow> rows;
};

// Throws std::invalid_argument "source:line:col: ..." if a row's cell count differs from the header's.
CsvTable ParseCsv(const std::string& text, const std::string& source);

// Index of a header cell, -1 if absent.
int FindColumn(const CsvTable& table, const std::string& name);

}  // namespace kincal
