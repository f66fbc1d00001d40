// module.cpp — clhair._clhair, the compiled half of the Python package (python/clhair wraps
// it): one exception type carrying clhair::Error's one line, and the parts bound in their
// own files (bindings.h).
#include <nanobind/nanobind.h>

#include "bindings.h"
#include "clhair/error.h"

NB_MODULE(_clhair, m) {
  namespace nb = nanobind;
  m.doc() = "clhair's renderer, scenes and grooms (use the clhair package, not this module)";
  nb::exception<clhair::Error>(m, "Error", PyExc_RuntimeError);
  clhair::py::bindGroom(m);
  clhair::py::bindScene(m);
  clhair::py::bindRenderer(m);
  clhair::py::bindImages(m);
}
