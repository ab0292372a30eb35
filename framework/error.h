#pragma once
// Bad input is reported as std::invalid_argument whose message is one line naming where the problem is
// (file, line, column) and what was expected. The command line turns it into exit status 2.
#include <stdexcept>
#include <string>

namespace kincal {

// "file:line:column: what". line and column are 1-based; 0 leaves them out.
std::string Located(const std::string& file, int line, int column, const std::string& what);

[[noreturn]] void ThrowInputError(const std::string& file, int line, int column, const std::string& what);
[[noreturn]] void ThrowInputError(const std::string& what);

}  // namespace kincal
