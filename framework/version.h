#pragma once
// The kincal version of these headers (framework/CMakeLists.txt checks it against project(VERSION)). A
// plugin records the version it was built against (framework/plugin.h); kincal refuses another.
#define KINCAL_VERSION_STRING "0.1.0"
