// The headers every test program is compiled with first, precompiled once per build (tests/CMakeLists.txt,
// KINCAL_PCH): GoogleTest, the library set (cmake/pch_library.h) and the kincal headers most tests include.
// Each test still includes what it uses.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "cmake/pch_library.h"
#include "estimators/estimator.h"
#include "framework/dataset.h"
#include "framework/math.h"
#include "framework/random.h"
#include "robot/prediction.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"
#include "tests/support/test_util.h"
