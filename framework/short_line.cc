#include "framework/short_line.h"

#include <vector>

namespace kincal {

std::string ShortLine(const std::string& text, size_t max_chars, const std::string& where_full) {
  if (text.size() <= max_chars) return text;
  // Top-level separators: a ", " list if the message has one outside brackets, else single spaces.
  std::vector<size_t> commas, spaces;
  int depth = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '(' || c == '[' || c == '{') ++depth;
    if ((c == ')' || c == ']' || c == '}') && depth > 0) --depth;
    if (depth == 0 && c == ',' && i + 1 < text.size() && text[i + 1] == ' ') commas.push_back(i);
    if (depth == 0 && c == ' ') spaces.push_back(i);
  }
  const std::vector<size_t>& separators = commas.empty() ? spaces : commas;
  size_t kept = 0;  // separators before the cut
  while (kept < separators.size() && separators[kept] <= max_chars) ++kept;
  if (kept == 0 || kept == separators.size()) return text;  // nothing to count: leave it whole
  const size_t more = separators.size() - kept + 1;
  return text.substr(0, separators[kept - 1]) + " ... and " + std::to_string(more) + " more" + where_full;
}

}  // namespace kincal
