// The headers every test program is compiled with first, precompiled once per build (tests/CMakeLists.txt,
// KINCAL_PCH): GoogleTest and the library set (cmake/pch_library.h). Third-party and standard headers
// only: a kincal header here would hide a test's missing include.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "cmake/pch_library.h"
