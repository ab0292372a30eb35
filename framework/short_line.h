#pragma once
// Messages for a terminal: long lists shortened with a count of what was left out.
#include <cstddef>
#include <string>

namespace kincal {

// A message of at most about max_chars for a terminal line: a longer one (a list of parameter names) is
// cut after a whole item of its list (items: separated by ", " outside brackets, or by spaces when there is
// no such comma) and ends "... and N more" followed by `where_full` (where the whole message is).
std::string ShortLine(const std::string& text, size_t max_chars, const std::string& where_full);

}  // namespace kincal
