#pragma once
// The registry of compensators/builtin.cc, writable: methods from outside kincal (plugins, framework/plugin.h;
// Python's register_compensator) are added to it at run time. Readers use Compensators() (compensators/compensator.h).
// Not locked: add before methods run.
#include "compensators/compensator.h"

namespace kincal {

CompensatorRegistry& MutableCompensators();

}  // namespace kincal
