#include "framework/error.h"

namespace kincal {

std::string Located(const std::string& file, int line, int column, const std::string& what) {
  std::string out = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    out += ":" + std::to_string(line);
    if (column > 0) out += ":" + std::to_string(column);
  }
  return out + ": " + what;
}

void ThrowInputError(const std::string& file, int line, int column, const std::string& what) {
  throw std::invalid_argument(Located(file, line, column, what));
}

void ThrowInputError(const std::string& what) { throw std::invalid_argument(what); }

}  // namespace kincal
