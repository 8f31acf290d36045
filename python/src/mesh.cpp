// rgbmesh.Mesh: an RgbMesh, built from numpy arrays and read back as numpy arrays (one copy
// per array, no per-element Python), refined with the GIL released.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <string>

#include "bindings.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"

namespace py = pybind11;

namespace rgbmesh::python {

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Indices = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// An (n, 3) array's rows, refused with the reason if it is not one.
template <class Array>
void require_rows_of_three(const Array& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InputError(std::string(what) + ": an (n, 3) array is needed, got " + std::to_string(a.ndim()) + " dimensions" +
                     (a.ndim() == 2 ? " and " + std::to_string(a.shape(1)) + " columns" : std::string()));
}

RgbMesh from_arrays(const Doubles& points, const Indices& triangles) {
  require_rows_of_three(points, "points");
  require_rows_of_three(triangles, "triangles");
  const auto n = static_cast<std::size_t>(points.shape(0)), m = static_cast<std::size_t>(triangles.shape(0));
  std::vector<Vec3> p(n);
  const double* x = points.data();
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z))
      throw InputError("points: point " + std::to_string(i) + " is not finite");
  }
  std::vector<std::array<std::int32_t, 3>> t(m);
  const std::int64_t* c = triangles.data();
  for (std::size_t i = 0; i < m; ++i)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = c[3 * i + static_cast<std::size_t>(k)];
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw InputError("triangles: triangle " + std::to_string(i) + " has vertex index " + std::to_string(v) +
                         ", out of range (there are " + std::to_string(n) + " points)");
      t[i][static_cast<std::size_t>(k)] = static_cast<std::int32_t>(v);
    }
  return RgbMesh::from_triangles(p, t);
}

// Copies into a new numpy array of `rows` x `columns`.
template <class T, class Fill>
py::array_t<T> make_array(std::size_t rows, std::size_t columns, Fill&& fill) {
  py::array_t<T> out(columns == 1 ? std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows)}
                                  : std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns)});
  fill(out.mutable_data());
  return out;
}

py::array_t<double> points_of(const MeshSnapshot& s) {
  return make_array<double>(s.points.size(), 3, [&](double* d) {
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      d[3 * i] = s.points[i].x;
      d[3 * i + 1] = s.points[i].y;
      d[3 * i + 2] = s.points[i].z;
    }
  });
}

}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<RgbMesh>(m, "Mesh", "An RGB subdivision mesh: its base mesh and the vertices inserted since.")
      .def_static("from_arrays", &from_arrays, py::arg("points"), py::arg("triangles"),
                  "A base mesh from an (n, 3) float array of points and an (m, 3) integer array of "
                  "counter-clockwise triangles, validated as the mesh files are (ValueError naming the element).")
      .def_property_readonly("num_vertices", &RgbMesh::num_vertices)
      .def_property_readonly("num_triangles", &RgbMesh::num_triangles)
      .def_property_readonly("max_level", &RgbMesh::max_level)
      .def(
          "control_points", [](const RgbMesh& mesh) { return points_of(mesh.snapshot(RgbMesh::Points::control)); },
          "The vertices' control points at their shown level, (n, 3), in the order of triangles().")
      .def(
          "limit_positions",
          [](RgbMesh& mesh) {
            {
              py::gil_scoped_release release;
              mesh.compute_limits();
            }
            return points_of(mesh.snapshot(RgbMesh::Points::limit));
          },
          "The vertices' positions on the Loop limit surface, (n, 3), in the order of triangles().")
      .def(
          "triangles",
          [](const RgbMesh& mesh) {
            const MeshSnapshot s = mesh.snapshot();
            return make_array<std::int32_t>(s.triangles.size(), 3, [&](std::int32_t* d) {
              for (std::size_t i = 0; i < s.triangles.size(); ++i)
                for (std::size_t k = 0; k < 3; ++k) d[3 * i + k] = s.triangles[i][k];
            });
          },
          "The triangles, (m, 3) indices into the point arrays, counter-clockwise.")
      .def(
          "vertex_levels",
          [](const RgbMesh& mesh) {
            const MeshSnapshot s = mesh.snapshot();
            return make_array<std::uint8_t>(s.vertex_level.size(), 1, [&](std::uint8_t* d) {
              std::copy(s.vertex_level.begin(), s.vertex_level.end(), d);
            });
          },
          "Each vertex's insertion level (0: a base vertex).")
      .def(
          "refine_uniform",
          [](RgbMesh& mesh, int level) {
            if (level < 0 || level > kMaxLevel)
              throw InputError("level " + std::to_string(level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
            py::gil_scoped_release release;
            const RefinementResult r = selective_refinement(mesh, UniformLevel(level));
            return r.splits;
          },
          py::arg("level"), "Refines (or coarsens) to the uniform mesh of this level; returns the vertices inserted.")
      .def("validate", [](const RgbMesh& mesh) { return mesh.validate(); },
           "'' when every invariant holds (conformity, manifoldness, orientation, colours, levels), else the first violation.");
}

}  // namespace rgbmesh::python
