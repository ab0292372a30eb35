#pragma once
// The parts of the `kincal` Python module, each defined in its own file.
#include <pybind11/pybind11.h>

namespace kincal::python {

void BindRobot(pybind11::module_& m);    // robot_bindings.cc
void BindDataset(pybind11::module_& m);  // dataset_bindings.cc
void BindMethods(pybind11::module_& m);  // methods_bindings.cc: simulate, identify, predict, ...
void BindPlugins(pybind11::module_& m);  // plugin_bindings.cc: register_estimator, register_compensator, load_plugin

}  // namespace kincal::python
