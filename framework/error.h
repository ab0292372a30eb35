#pragma once
// Bad input is reported as std::invalid_argument whose message is one line naming where the problem is
// (file, line, column) and what was expected. The command line turns it into exit status 2.
#include <stdexcept>
#include <string>

namespace kincal {

// `text` with control bytes written as \xNN. Messages quote what the input holds ("unknown key '...'",
// "got '...'"); a quoted newline, carriage return or NUL would break the one-line promise (and the
// terminal).
std::string OneLine(const std::string& text);

// "file:line:column: what" (what through OneLine). line and column are 1-based; 0 leaves them out.
std::string Located(const std::string& file, int line, int column, const std::string& what);

[[noreturn]] void ThrowInputError(const std::string& file, int line, int column, const std::string& what);
[[noreturn]] void ThrowInputError(const std::string& what);

}  // namespace kincal
