#include "framework/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace kincal {

std::string OneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      out += escape;
    } else {
      out += ch;
    }
  }
  return out;
}

std::string Located(const std::string& file, int line, int column, const std::string& what) {
  std::string out = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    out += ":" + std::to_string(line);
    if (column > 0) out += ":" + std::to_string(column);
  }
  return out + ": " + OneLine(what);
}

void ThrowInputError(const std::string& file, int line, int column, const std::string& what) {
  throw std::invalid_argument(Located(file, line, column, what));
}

void ThrowInputError(const std::string& what) { throw std::invalid_argument(OneLine(what)); }

void ThrowIoError(const std::string& path, const std::string& what) {
  const int error = errno;
  throw IoError(OneLine(path + ": " + what + (error != 0 ? std::string(": ") + std::strerror(error) : std::string())));
}

}  // namespace kincal
