#include "framework/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include "framework/error.h"
#include "framework/memory.h"

namespace kincal {
namespace {

// fsync(2) of a file or folder by path. A rename is atomic but not durable: after a power cut the new
// name can point at a file whose blocks were never written (ext4 with delalloc, xfs) unless the data
// reached the disk before the rename, and the rename itself is only on disk once the folder is synced.
bool SyncPath(const std::string& path, bool folder) {
  const int fd = ::open(path.c_str(), (folder ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw std::invalid_argument(path + ": folder '" + dir.string() + "' does not exist");
  const fs::path temp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) ThrowIoError(path, "cannot write (" + temp.string() + ")");
    try {
      writer(out);
    } catch (...) {
      out.close();
      std::remove(temp.c_str());
      throw;
    }
    out.flush();
    out.close();
    if (!out) {
      const int error = errno;
      std::remove(temp.c_str());
      errno = error;
      ThrowIoError(path, "write failed");
    }
  }
  if (!SyncPath(temp.string(), false)) {
    const int error = errno;
    std::remove(temp.c_str());
    errno = error;
    ThrowIoError(path, "cannot flush to disk (" + temp.string() + ")");
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    std::remove(temp.c_str());
    throw IoError(OneLine(path + ": cannot rename into place: " + ec.message()));
  }
  // The new file is complete on disk whatever happens now; a folder that cannot be synced (some network
  // file systems refuse fsync on folders) only loses durability of the name, so it is not an error.
  SyncPath(dir.string(), true);
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << content; });
}

std::string ReadFileToString(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw std::invalid_argument(path + ": is a folder, expected a file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::invalid_argument(path + ": cannot open file");
  // One read into a string of the file's size (a stringstream grows by copies: slow for large datasets).
  const std::streamoff size = in.tellg();
  if (size > 0) {
    CheckMemory(path, 0, static_cast<double>(size), "the file");
    std::string text(static_cast<size_t>(size), '\0');
    in.seekg(0);
    if (in.read(text.data(), size)) return text;
    in.clear();
    in.seekg(0);
  }
  // A pipe or a device has no size: read in blocks, up to the memory there is (/dev/zero never ends).
  const double limit = AvailableMemoryBytes() > 0.0 ? AvailableMemoryBytes() / 2.0 : 1e12;
  std::string text;
  char block[1 << 16];
  while (in.read(block, sizeof(block)) || in.gcount() > 0) {
    text.append(block, static_cast<size_t>(in.gcount()));
    if (static_cast<double>(text.size()) > limit) {
      throw std::invalid_argument(path + ": more than " + std::to_string(static_cast<long long>(limit / 1e6)) +
                                  " MB and still not at its end: not a file kincal can read");
    }
  }
  if (in.bad()) throw std::invalid_argument(path + ": read error");
  return text;
}

}  // namespace kincal
