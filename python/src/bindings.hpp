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
RgbMesh mesh_from_arrays(const DoubleArray& points, const IndexArray& triangles, const std::string& what = "",
                         const SharpFeatures& sharp = {});

/// Sharp features from numpy arrays (any may be None): edges (m, 2) base vertices and their
/// sharpness (m,) (10 when None), vertices (k,) and theirs (k,), the creasing method's name.
SharpFeatures sharp_features_of(const pybind11::object& edges, const pybind11::object& edge_sharpness,
                                const pybind11::object& vertices, const pybind11::object& vertex_sharpness,
                                const std::string& method);
/// The features as a dict of those arrays: edges, edge_sharpness, vertices, vertex_sharpness, method.
pybind11::dict sharp_features_dict(const SharpFeatures& sharp);

/// A new numpy array of rows x columns (1: a vector), filled by fill(T* data).
template <class T, class Fill>
pybind11::array_t<T> make_array(std::size_t rows, std::size_t columns, Fill&& fill) {
  using pybind11::ssize_t;
  pybind11::array_t<T> out(columns == 1 ? std::vector<ssize_t>{static_cast<ssize_t>(rows)}
                                        : std::vector<ssize_t>{static_cast<ssize_t>(rows), static_cast<ssize_t>(columns)});
  fill(out.mutable_data());
  return out;
}
/// A new numpy array of rows x columns from `data`, converted element by element.
template <class T, class Source>
pybind11::array_t<T> array_of(std::size_t rows, std::size_t columns, const Source* data) {
  return make_array<T>(rows, columns, [&](T* d) {
    for (std::size_t i = 0; i < rows * columns; ++i) d[i] = static_cast<T>(data[i]);
  });
}

/// Ctrl-C: asks Python for pending signals (the GIL held); a KeyboardInterrupt then unwinds
/// from here, between two operations of the library, which leave the mesh valid.
inline void throw_if_interrupted() {
  if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
}
/// The same from code that released the GIL: takes it back for the check.
inline void check_signals() {
  pybind11::gil_scoped_acquire gil;
  throw_if_interrupted();
}

}  // namespace rgbmesh::python
