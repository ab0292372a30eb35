#include "framework/csv.h"

#include "framework/error.h"

namespace kincal {
namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

CsvRow SplitLine(const std::string& line, int line_number) {
  CsvRow row;
  row.line = line_number;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    const std::string cell = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    row.cells.push_back(Trim(cell));
    row.columns.push_back(static_cast<int>(start) + 1);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return row;
}

}  // namespace

CsvTable ParseCsv(const std::string& text, const std::string& source) {
  CsvTable table;
  bool have_header = false;
  int line_number = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) {
      if (end == text.size()) break;
      continue;
    }
    if (trimmed[0] == '#') {
      if (!have_header) table.comments.push_back(Trim(trimmed.substr(1)));
      continue;
    }
    CsvRow row = SplitLine(line, line_number);
    if (!have_header) {
      table.header = row;
      have_header = true;
      continue;
    }
    if (row.cells.size() != table.header.cells.size()) {
      ThrowInputError(source, line_number, 1,
                      "expected " + std::to_string(table.header.cells.size()) + " comma-separated values, got " +
                          std::to_string(row.cells.size()));
    }
    table.rows.push_back(std::move(row));
    if (end == text.size()) break;
  }
  if (!have_header) ThrowInputError(source, 1, 1, "empty file: expected a header row");
  return table;
}

int FindColumn(const CsvTable& table, const std::string& name) {
  for (size_t i = 0; i < table.header.cells.size(); ++i) {
    if (table.header.cells[i] == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace kincal
