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

// A file that cannot be written or made durable (permissions, a full disk, a failed fsync or rename):
// one line naming the file, what failed and the system's reason. Not bad input, but the command line
// answers it the same way, exit status 2 and that line (docs/RELIABILITY.md).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// Throws IoError "path: what: <strerror(errno)>" (errno as the failed call left it).
[[noreturn]] void ThrowIoError(const std::string& path, const std::string& what);

}  // namespace kincal
