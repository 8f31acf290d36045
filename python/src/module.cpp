// rgbmesh._rgbmesh: the extension module. The library's errors become Python exceptions with
// its messages: bad input (rgbmesh::InputError) a ValueError subclass, a precondition an
// exception type of its own.

#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/mesh.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_rgbmesh, m) {
  m.doc() = "RGB subdivision meshes (the C++ library rgbmesh)";
  static py::exception<rgbmesh::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<rgbmesh::PreconditionError> precondition_error(m, "PreconditionError", PyExc_RuntimeError);
  static py::exception<rgbmesh::OutputError> output_error(m, "OutputError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const rgbmesh::InputError& e) {
      input_error(e.what());
    } catch (const rgbmesh::PreconditionError& e) {
      precondition_error(e.what());
    } catch (const rgbmesh::OutputError& e) {
      output_error(e.what());
    }
  });
  rgbmesh::python::bind_mesh(m);
  rgbmesh::python::bind_io(m);
  rgbmesh::python::bind_state(m);
#if defined(RGBMESH_PYTHON_FEM)
  rgbmesh::python::bind_fem(m);
#endif
#if defined(RGBMESH_PYTHON_FIT)
  rgbmesh::python::bind_fit(m);
#endif
}
