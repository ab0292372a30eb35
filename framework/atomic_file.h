#pragma once
// Outputs are written to a temporary file beside the target and renamed into place, so a failure never
// leaves a half-written or changed output.
#include <functional>
#include <ostream>
#include <string>

namespace kincal {

// Throws std::runtime_error if the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& content);
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer);

std::string ReadFileToString(const std::string& path);  // throws std::invalid_argument if unreadable

}  // namespace kincal
