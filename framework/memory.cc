#include "framework/memory.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <sys/resource.h>

#include "framework/error.h"

namespace kincal {

double AvailableMemoryBytes() {
  double available = 0.0;
  const auto take = [&available](double bytes) {
    if (bytes > 0.0 && (available == 0.0 || bytes < available)) available = bytes;
  };
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kb = 0.0;
  std::string unit;
  while (meminfo >> key >> kb >> unit) {
    if (key == "MemAvailable:") {
      take(kb * 1024.0);
      break;
    }
  }
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) take(static_cast<double>(limit.rlim_cur));
  if (const char* mb = std::getenv("KINCAL_MEMORY_LIMIT_MB")) take(std::atof(mb) * 1024.0 * 1024.0);
  return available;
}

void CheckMemory(const std::string& source, int line, double bytes, const std::string& what) {
  const double available = AvailableMemoryBytes();
  if (available <= 0.0 || bytes <= available) return;
  char text[160];
  std::snprintf(text, sizeof(text), "needs about %.1f GB of memory, %.1f GB available", bytes / 1e9, available / 1e9);
  ThrowInputError(source, line, 0, what + " " + text);
}

}  // namespace kincal
