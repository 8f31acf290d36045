#pragma once
// The pieces of the rgbmesh._rgbmesh extension, each binding one part of the library.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh::python {

void bind_mesh(pybind11::module_& m);
void bind_io(pybind11::module_& m);  // after bind_mesh (it adds Mesh.write)
void bind_state(pybind11::module_& m);  // after bind_mesh (Mesh.state, Mesh.from_state)
void bind_fem(pybind11::module_& m);  // with RGBMESH_PYTHON_FEM (rgbmesh::fem and rgbmesh::adapt built)
void bind_fit(pybind11::module_& m);  // with RGBMESH_PYTHON_FIT (rgbmesh::fit built)

using DoubleArray = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;
using IndexArray = pybind11::array_t<std::int64_t, pybind11::array::c_style | pybind11::array::forcecast>;

/// The rows of an (n, 3) array of finite numbers; InputError naming `what` and the bad row.
std::vector<Vec3> points_of_array(const DoubleArray& points, const char* what);
/// A base mesh from arrays, checked as the mesh files are; errors name `what` ("base") first.
RgbMesh mesh_from_arrays(const DoubleArray& points, const IndexArray& triangles, const std::string& what = "");

/// A new numpy array of rows x columns (1: a vector) from `data`, converted element by element.
template <class T, class Source>
pybind11::array_t<T> array_of(std::size_t rows, std::size_t columns, const Source* data) {
  using pybind11::ssize_t;
  pybind11::array_t<T> out(columns == 1 ? std::vector<ssize_t>{static_cast<ssize_t>(rows)}
                                        : std::vector<ssize_t>{static_cast<ssize_t>(rows), static_cast<ssize_t>(columns)});
  T* d = out.mutable_data();
  for (std::size_t i = 0; i < rows * columns; ++i) d[i] = static_cast<T>(data[i]);
  return out;
}

}  // namespace rgbmesh::python
