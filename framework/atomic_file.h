#pragma once
// Outputs are written to a temporary file beside the target and renamed into place, so a failure never
// leaves a half-written or changed output. The temporary is synced (fsync) before the rename and the
// folder after it, so a power cut leaves the old file or the new one.
#include <functional>
#include <ostream>
#include <string>

namespace kincal {

// Throws std::invalid_argument when the folder does not exist, IoError (framework/error.h) when the file
// cannot be written, synced or renamed into place (a full disk, permissions).
void WriteFileAtomically(const std::string& path, const std::string& content);
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer);

std::string ReadFileToString(const std::string& path);  // throws std::invalid_argument if unreadable

}  // namespace kincal
