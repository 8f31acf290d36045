#pragma once
// The pieces of the rgbmesh._rgbmesh extension, each binding one part of the library.

#include <pybind11/pybind11.h>

namespace rgbmesh::python {

void bind_mesh(pybind11::module_& m);
void bind_io(pybind11::module_& m);  // after bind_mesh (it adds Mesh.write)

}  // namespace rgbmesh::python
