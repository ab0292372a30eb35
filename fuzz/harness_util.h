#pragma once
// What every harness checks (fuzz/harnesses.h): the promise about bad input, and findings.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

namespace kincal::fuzz {

// A finding: print what broke the promise and abort, so that libFuzzer (or the replay test) stops there.
[[noreturn]] inline void Finding(const std::string& what) {
  std::fprintf(stderr, "kincal fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// The promise about bad input: std::invalid_argument, one line, naming the file first. Readers are
// given `source` as the file's name; a message that does not start with it would reach the user
// without saying which file is wrong. An empty `source` checks one line only (a method refusing data
// it was given in memory; the command line names the file in front, apps/cli_util.h).
template <typename Body>
bool Accepts(const std::string& source, Body&& body) {
  try {
    body();
    return true;
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    if (message.find('\n') != std::string::npos) Finding("message of several lines: " + message);
    if (message.empty()) Finding("an error without a message");
    if (message.compare(0, source.size(), source) != 0) Finding("message does not name " + source + ": " + message);
    return false;
  } catch (const std::bad_alloc&) {
    Finding("std::bad_alloc: a reader tried to allocate without a limit");
  } catch (const std::exception& e) {
    Finding(std::string("exception other than std::invalid_argument: ") + e.what());
  } catch (...) {
    Finding("non-standard exception");
  }
}

inline std::string Text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

inline void ExpectFinite(double value, const std::string& what) {
  if (!std::isfinite(value)) Finding(what + " is not finite");
}

}  // namespace kincal::fuzz
