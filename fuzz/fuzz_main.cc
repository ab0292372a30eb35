// libFuzzer entry point of one harness (KINCAL_HARNESS_FUNCTION names it; fuzz/CMakeLists.txt builds one
// program per harness).
#include "fuzz/harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return kincal::fuzz::KINCAL_HARNESS_FUNCTION(data, size);
}
