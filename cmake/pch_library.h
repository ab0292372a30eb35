// The headers every build precompiles once for its libraries (CMakeLists.txt, KINCAL_PCH): the third-party
// and standard headers most of kincal's sources include, and only those (a kincal header here would hide
// a missing include).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>
