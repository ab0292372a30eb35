#pragma once
// The registry of estimators/builtin.cc, writable: methods from outside kincal (plugins, framework/plugin.h;
// Python's register_estimator) are added to it at run time. Readers use Estimators() (estimators/estimator.h). Not
// locked: add before methods run.
#include "estimators/estimator.h"

namespace kincal {

EstimatorRegistry& MutableEstimators();

}  // namespace kincal
