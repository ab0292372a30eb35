// The Python module `kincal`: kincal's robots, datasets and methods with numpy arrays in and
// out, SI units (metres, radians). Bad input raises kincal.Error (a ValueError) with the one-line
// message the command line prints.
#include "python/bindings.h"
#include "python/conversions.h"

PYBIND11_MODULE(kincal, m) {
  m.doc() = "kincal: kinematic calibration of serial robot arms (SI units: metres, radians).";
  m.attr("__version__") = "0.1.0";
  kincal::python::RegisterErrors(m);
  kincal::python::BindRobot(m);
  kincal::python::BindDataset(m);
  kincal::python::BindMethods(m);
  kincal::python::BindPlugins(m);
}
