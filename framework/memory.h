#pragma once
// Memory checks before large allocations: an input too large for the machine is refused with a message
// (exit status 2) instead of being met by the kernel's out-of-memory killer, which ends the process
// without a word, or by swapping for hours.
#include <cstddef>
#include <string>

namespace kincal {

// Bytes this process may still allocate: the smallest of MemAvailable (/proc/meminfo), the address-space
// limit (ulimit -v) and KINCAL_MEMORY_LIMIT_MB when set (to test, or to share a machine). 0 = unknown.
double AvailableMemoryBytes();

// Throws std::invalid_argument "source[:line]: what needs about X GB of memory, Y GB available" when
// `bytes` exceeds AvailableMemoryBytes(). `line` 0 leaves the line out.
void CheckMemory(const std::string& source, int line, double bytes, const std::string& what);

}  // namespace kincal
