// Mesh.state and Mesh.from_state: the RGB state (rgb_state.hpp) as numpy arrays, the arrays the
// .vtp/.vtu files carry, so that a mesh can travel through VTK or PyVista objects (and any
// writer of theirs) and come back as the same RGB mesh.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "bindings.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/rgb_state.hpp"

namespace py = pybind11;

namespace rgbmesh::python {

namespace {

using Ints = py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>;
using Bytes = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

template <std::size_t N>
std::vector<std::array<std::int32_t, N>> rows_of(const Ints& a, std::size_t rows, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(N) || (rows != 0 && static_cast<std::size_t>(a.shape(0)) != rows))
    throw InputError(std::string(what) + ": an array of " + (rows ? std::to_string(rows) : std::string("m")) + " rows of " +
                     std::to_string(N) + " integers is needed");
  std::vector<std::array<std::int32_t, N>> out(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t i = 0; i < out.size(); ++i)
    for (std::size_t k = 0; k < N; ++k) out[i][k] = a.data()[N * i + k];
  return out;
}

template <class T, class Array>
std::vector<T> values_of(const Array& a, std::size_t count, const char* what) {
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count)
    throw InputError(std::string(what) + ": " + std::to_string(count) + " values are needed (one per row), got " +
                     (a.ndim() == 1 ? std::to_string(a.shape(0)) : std::to_string(a.ndim()) + " dimensions"));
  return std::vector<T>(a.data(), a.data() + count);
}

py::dict state_of(const RgbMesh& mesh) {
  MeshSnapshot rows;  // (save_state needs only the points' vertices, in the arrays' order)
  rows.vertex_handle.reserve(mesh.num_vertices());
  for (const VertexHandle v : mesh.vertices()) rows.vertex_handle.push_back(v);
  const RgbState s = save_state(mesh, rows);
  py::dict d;
  d["version"] = s.version;
  d["base_points"] = array_of<double>(s.base_points.size(), 3, s.base_points.empty() ? nullptr : &s.base_points[0].x);
  d["base_triangles"] =
      array_of<std::int32_t>(s.base_triangles.size(), 3, s.base_triangles.empty() ? nullptr : s.base_triangles[0].data());
  d["base_vertex"] = array_of<std::int32_t>(s.base_vertex.size(), 1, s.base_vertex.data());
  d["parents"] = array_of<std::int32_t>(s.parents.size(), 2, s.parents.empty() ? nullptr : s.parents[0].data());
  if (!s.sharp.empty()) {
    const py::dict sharp = sharp_features_dict(s.sharp);
    d["sharp_edges"] = sharp["edges"];
    d["edge_sharpness"] = sharp["edge_sharpness"];
    d["sharp_vertices"] = sharp["vertices"];
    d["vertex_sharpness"] = sharp["vertex_sharpness"];
    d["crease_method"] = sharp["method"];
  }
  return d;
}

py::tuple from_state(const DoubleArray& base_points, const Ints& base_triangles, const Ints& base_vertex,
                     const Ints& parents, const std::optional<Ints>& triangles, const std::optional<Bytes>& vertex_levels,
                     const std::optional<Bytes>& triangle_levels, const std::optional<Bytes>& triangle_colors, int version,
                     const py::object& sharp_edges, const py::object& edge_sharpness, const py::object& sharp_vertices,
                     const py::object& vertex_sharpness, const std::string& crease_method) {
  if (version < 1 || version > RgbState::kVersion)
    throw InputError("RGB state version " + std::to_string(version) + ": this rgbmesh reads versions 1 to " +
                     std::to_string(RgbState::kVersion));
  RgbState s;
  s.version = version;
  s.base_points = points_of_array(base_points, "base_points");
  s.base_triangles = rows_of<3>(base_triangles, 0, "base_triangles");
  if (base_vertex.ndim() != 1) throw InputError("base_vertex: one value per point is needed");
  const auto n = static_cast<std::size_t>(base_vertex.shape(0));
  s.base_vertex = values_of<std::int32_t>(base_vertex, n, "base_vertex");
  s.parents = rows_of<2>(parents, n, "parents");
  s.sharp = sharp_features_of(sharp_edges, edge_sharpness, sharp_vertices, vertex_sharpness, crease_method);
  RestoreExpectations e;
  if (triangles) e.triangles = rows_of<3>(*triangles, 0, "triangles");
  if (vertex_levels) e.vertex_level = values_of<std::uint8_t>(*vertex_levels, n, "vertex_levels");
  if (triangle_levels) e.triangle_level = values_of<std::uint8_t>(*triangle_levels, e.triangles.size(), "triangle_levels");
  if (triangle_colors) e.triangle_color = values_of<std::uint8_t>(*triangle_colors, e.triangles.size(), "triangle_colors");
  RestoredMesh r;
  {
    py::gil_scoped_release release;
    r = restore_state(s, e);
  }
  // Where each of the state's points is among the new mesh's rows (its vertices in slot order).
  std::vector<std::int32_t> row_of_slot(static_cast<std::size_t>(r.mesh.vertex_slots()), -1), rows(n);
  std::int32_t next = 0;
  for (const VertexHandle v : r.mesh.vertices()) row_of_slot[static_cast<std::size_t>(v.idx)] = next++;
  for (std::size_t i = 0; i < n; ++i) rows[i] = row_of_slot[static_cast<std::size_t>(r.vertex[i].idx)];
  return py::make_tuple(std::move(r.mesh), array_of<std::int32_t>(n, 1, rows.data()));
}

}  // namespace

void bind_state(py::module_& m) {
  py::class_<RgbMesh>(m.attr("Mesh"))
      .def("copy", [](const RgbMesh& mesh) { return RgbMesh(mesh); }, "An independent copy (the same handles and rows).")
      .def("__copy__", [](const RgbMesh& mesh) { return RgbMesh(mesh); })
      .def("__deepcopy__", [](const RgbMesh& mesh, py::dict) { return RgbMesh(mesh); }, py::arg("memo"))
      // Pickling (multiprocessing, storing meshes) goes through the RGB state and the triangles,
      // as the files do: the unpickled mesh is the same RGB mesh, rows in the state's order.
      .def(py::pickle(
          [](const RgbMesh& mesh) {
            const py::dict state = state_of(mesh);
            const py::dict sharp = sharp_features_dict(mesh.sharp_features());
            return py::make_tuple(state["version"], state["base_points"], state["base_triangles"], state["base_vertex"],
                                  state["parents"], py::cast(mesh).attr("triangles")(), sharp["edges"],
                                  sharp["edge_sharpness"], sharp["vertices"], sharp["vertex_sharpness"], sharp["method"]);
          },
          [](const py::tuple& t) {
            // 6 items: pickled before sharp features existed.
            if (t.size() != 6 && t.size() != 11)
              throw InputError("unpickling a Mesh: 6 or 11 items expected, got " + std::to_string(t.size()));
            const bool sharp = t.size() == 11;
            py::tuple restored = from_state(
                py::cast<DoubleArray>(t[1]), py::cast<Ints>(t[2]), py::cast<Ints>(t[3]), py::cast<Ints>(t[4]),
                py::cast<Ints>(t[5]), std::nullopt, std::nullopt, std::nullopt, t[0].cast<int>(),
                sharp ? py::object(t[6]) : py::none(), sharp ? py::object(t[7]) : py::none(),
                sharp ? py::object(t[8]) : py::none(), sharp ? py::object(t[9]) : py::none(),
                sharp ? t[10].cast<std::string>() : std::string("uniform"));
            return std::move(restored[0].cast<RgbMesh&>());
          }))
      .def("state", &state_of,
           "The RGB state as arrays, what .vtp/.vtu files carry (format version 1, or 2 with sharp features): "
           "base_points and base_triangles (the base mesh, exactly), per row of the point arrays base_vertex (its "
           "base index, -1 if inserted) and parents (the two rows whose edge it split, -1 -1 for a base vertex), "
           "and where the base mesh has sharp features sharp_edges, edge_sharpness, sharp_vertices, "
           "vertex_sharpness and crease_method (Mesh.from_state takes them back).")
      .def_static("from_state", &from_state, py::arg("base_points"), py::arg("base_triangles"), py::arg("base_vertex"),
                  py::arg("parents"), py::kw_only(), py::arg("triangles") = py::none(),
                  py::arg("vertex_levels") = py::none(), py::arg("triangle_levels") = py::none(),
                  py::arg("triangle_colors") = py::none(), py::arg("version") = RgbState::kVersion,
                  py::arg("sharp_edges") = py::none(), py::arg("edge_sharpness") = py::none(),
                  py::arg("sharp_vertices") = py::none(), py::arg("vertex_sharpness") = py::none(),
                  py::arg("crease_method") = "uniform",
                  "Rebuilds the mesh from its state (Mesh.state()) and checks it against what is given: its triangles "
                  "(which also settle the one choice a vertex set leaves open, a trapezoid's diagonal), levels and "
                  "colours. Returns (mesh, rows): rows[i] is the row of the state's point i in the new mesh's arrays. "
                  "An inconsistent state: ValueError saying what is wrong.");
}

}  // namespace rgbmesh::python
