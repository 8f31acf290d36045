// rgbmesh.Mesh: an RgbMesh, built from numpy arrays and read back as numpy arrays (one copy
// per array, no per-element Python), refined with the GIL released.

#include "rgbmesh/mesh.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/refinement.hpp"

namespace py = pybind11;

namespace rgbmesh::python {

namespace {

// An (n, 3) array's rows, refused with the reason if it is not one.
template <class Array>
void require_rows_of_three(const Array& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InputError(std::string(what) + ": an (n, 3) array is needed, got " + std::to_string(a.ndim()) + " dimensions" +
                     (a.ndim() == 2 ? " and " + std::to_string(a.shape(1)) + " columns" : std::string()));
}



// Each live vertex's row in the point arrays (the vertices in slot order, as in a snapshot),
// by slot (-1: a free slot).
std::vector<std::int32_t> rows_of_slots(const RgbMesh& mesh) {
  std::vector<std::int32_t> row(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  std::int32_t next = 0;
  for (const VertexHandle v : mesh.vertices()) row[static_cast<std::size_t>(v.idx)] = next++;
  return row;
}

// Per-vertex and per-triangle arrays written straight from the mesh, in the snapshot's order
// (no snapshot of everything for one array), on every core with the GIL released. `value`
// must only read the mesh (limit positions must be known already: their cache is written
// when they are not).
template <class T, std::size_t Width, class Handle, class Range, class Value>
py::array_t<T> per_element(std::size_t count, const Range& range, Value&& value) {
  std::vector<Handle> handles;
  handles.reserve(count);
  for (const Handle h : range) handles.push_back(h);
  return make_array<T>(handles.size(), Width, [&](T* d) {
    py::gil_scoped_release release;
    rgbmesh::detail::parallel_for(handles.size(), std::size_t{1} << 14, rgbmesh::detail::hardware_threads(),
                                  [&](std::size_t, std::size_t i) { value(handles[i], d + Width * i); });
  });
}
// A point into a row of an (n, 3) array.
void put(const Vec3& p, double* row) { row[0] = p.x, row[1] = p.y, row[2] = p.z; }

template <class T, std::size_t Width, class Value>
py::array_t<T> per_vertex(const RgbMesh& mesh, Value&& value) {
  return per_element<T, Width, VertexHandle>(mesh.num_vertices(), mesh.vertices(), std::forward<Value>(value));
}
template <class T, std::size_t Width, class Value>
py::array_t<T> per_triangle(const RgbMesh& mesh, Value&& value) {
  return per_element<T, Width, TriangleHandle>(mesh.num_triangles(), mesh.triangles(), std::forward<Value>(value));
}

// Refinement options that let Ctrl-C through: every 65,536 operations the progress report
// takes the GIL back and asks Python for pending signals; a KeyboardInterrupt then unwinds
// from between two operations, leaving a valid mesh.
RefinementOptions interruptible(int max_level) {
  RefinementOptions o;
  o.max_level = max_level;
  o.progress = [](std::uint64_t, std::size_t) { check_signals(); };
  return o;
}

py::dict result_of(const RefinementResult& r) {
  py::dict d;
  d["splits"] = r.splits;
  d["removals"] = r.removals;
  return d;
}

// Refinement by the built-in criteria, in the order given by the tool's stages.
py::dict refine(RgbMesh& mesh, std::optional<int> uniform, std::optional<int> at_least,
                std::optional<std::array<double, 5>> ball, std::optional<double> max_edge, std::optional<double> tolerance,
                std::optional<std::size_t> budget, int max_level) {
  if (max_level < 0 || max_level > kMaxLevel)
    throw InputError("max_level " + std::to_string(max_level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
  const auto level_in_range = [](int level, const char* what) {
    if (level < 0 || level > kMaxLevel)
      throw InputError(std::string(what) + ": level " + std::to_string(level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
    return level;
  };
  if (max_edge && !(*max_edge > 0)) throw InputError("max_edge: must be positive");
  if (tolerance && !(*tolerance > 0)) throw InputError("tolerance: must be positive");
  if (ball && !((*ball)[3] > 0)) throw InputError("ball: the radius must be positive");
  const RefinementOptions o = interruptible(max_level);
  RefinementResult total;
  const auto run = [&](const LodCriterion& c) {
    RefinementResult r;
    {
      py::gil_scoped_release release;
      r = selective_refinement(mesh, c, o);
    }
    total.splits += r.splits;
    total.removals += r.removals;
  };
  if (uniform) run(UniformLevel(level_in_range(*uniform, "uniform")));
  if (at_least) run(AtLeastLevel(level_in_range(*at_least, "at_least")));
  if (ball)
    run(BallLevel(Vec3((*ball)[0], (*ball)[1], (*ball)[2]), (*ball)[3],
                  level_in_range(static_cast<int>((*ball)[4]), "ball")));
  if (max_edge) run(MaxEdgeLength(*max_edge));
  if (tolerance) run(GeometricTolerance(*tolerance));
  if (budget) run(TriangleBudget(*budget));
  return result_of(total);
}

// The user's own indicator: per triangle (the rows of triangles()) refine where above
// refine_above; per vertex (the rows of the point arrays) remove where below coarsen_below.
py::dict adapt_to(RgbMesh& mesh, std::optional<DoubleArray> triangle_values, double refine_above,
                  std::optional<DoubleArray> vertex_values, double coarsen_below, int max_level) {
  if (max_level < 0 || max_level > kMaxLevel)
    throw InputError("max_level " + std::to_string(max_level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
  // The rows of the arrays are the live elements in slot order (as triangles() and the point
  // arrays give them): the values go to the slots.
  std::vector<double> by_triangle, by_vertex;
  if (triangle_values) {
    if (triangle_values->ndim() != 1 || static_cast<std::size_t>(triangle_values->shape(0)) != mesh.num_triangles())
      throw InputError("triangle_values: one value per triangle is needed (" + std::to_string(mesh.num_triangles()) + ")");
    by_triangle.assign(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
    const double* value = triangle_values->data();
    for (const TriangleHandle t : mesh.triangles()) {
      if (!std::isfinite(*value))
        throw InputError("triangle_values: row " + std::to_string(value - triangle_values->data()) + " is not finite");
      by_triangle[static_cast<std::size_t>(t.idx)] = *value++;
    }
  }
  if (vertex_values) {
    if (vertex_values->ndim() != 1 || static_cast<std::size_t>(vertex_values->shape(0)) != mesh.num_vertices())
      throw InputError("vertex_values: one value per vertex is needed (" + std::to_string(mesh.num_vertices()) + ")");
    by_vertex.assign(static_cast<std::size_t>(mesh.vertex_slots()), 1e300);
    const double* value = vertex_values->data();
    for (const VertexHandle v : mesh.vertices()) {
      if (!std::isfinite(*value))
        throw InputError("vertex_values: row " + std::to_string(value - vertex_values->data()) + " is not finite");
      by_vertex[static_cast<std::size_t>(v.idx)] = *value++;
    }
  }
  const RefinementOptions o = interruptible(max_level);
  const FieldCriterion criterion(std::move(by_triangle), refine_above, std::move(by_vertex), coarsen_below);
  RefinementResult r;
  {
    py::gil_scoped_release release;
    r = selective_refinement(mesh, criterion, o);
  }
  return result_of(r);
}

}  // namespace

std::vector<Vec3> points_of_array(const DoubleArray& points, const char* what) {
  require_rows_of_three(points, what);
  std::vector<Vec3> p(static_cast<std::size_t>(points.shape(0)));
  const double* x = points.data();
  for (std::size_t i = 0; i < p.size(); ++i) {
    p[i] = Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z))
      throw InputError(std::string(what) + ": point " + std::to_string(i) + " is not finite");
  }
  return p;
}

SharpFeatures sharp_features_of(const py::object& edges, const py::object& edge_sharpness, const py::object& vertices,
                                const py::object& vertex_sharpness, const std::string& method) {
  SharpFeatures s;
  if (method == "chaikin")
    s.method = CreaseMethod::chaikin;
  else if (method != "uniform")
    throw InputError("crease_method '" + method + "': uniform or chaikin");
  using Floats = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const auto floats = [](const py::object& a, std::size_t n, const char* what) {
    std::vector<float> out(n, kInfiniteSharpness);
    if (a.is_none()) return out;
    const Floats f = py::cast<Floats>(a);
    if (f.ndim() != 1 || static_cast<std::size_t>(f.shape(0)) != n)
      throw InputError(std::string(what) + ": one value per row is needed (" + std::to_string(n) + ")");
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(f.data()[i]);
    return out;
  };
  if (!edges.is_none()) {
    const IndexArray e = py::cast<IndexArray>(edges);
    if (e.ndim() != 2 || e.shape(1) != 2) throw InputError("sharp_edges: an (m, 2) integer array is needed");
    const auto m = static_cast<std::size_t>(e.shape(0));
    const std::vector<float> w = floats(edge_sharpness, m, "edge_sharpness");
    for (std::size_t i = 0; i < m; ++i)
      s.edges.push_back({static_cast<std::int32_t>(e.data()[2 * i]), static_cast<std::int32_t>(e.data()[2 * i + 1]), w[i]});
  } else if (!edge_sharpness.is_none()) {
    throw InputError("edge_sharpness: needs sharp_edges");
  }
  if (!vertices.is_none()) {
    const IndexArray v = py::cast<IndexArray>(vertices);
    if (v.ndim() != 1) throw InputError("sharp_vertices: a (k,) integer array is needed");
    const auto k = static_cast<std::size_t>(v.shape(0));
    const std::vector<float> w = floats(vertex_sharpness, k, "vertex_sharpness");
    for (std::size_t i = 0; i < k; ++i) s.vertices.push_back({static_cast<std::int32_t>(v.data()[i]), w[i]});
  } else if (!vertex_sharpness.is_none()) {
    throw InputError("vertex_sharpness: needs sharp_vertices");
  }
  return s;
}

py::dict sharp_features_dict(const SharpFeatures& sharp) {
  py::dict d;
  std::vector<std::int32_t> ends;
  std::vector<double> edge_sharpness, vertex_sharpness;
  std::vector<std::int32_t> vertices;
  for (const SharpEdge& e : sharp.edges) {
    ends.push_back(e.a);
    ends.push_back(e.b);
    edge_sharpness.push_back(e.sharpness);
  }
  for (const SharpVertex& v : sharp.vertices) {
    vertices.push_back(v.v);
    vertex_sharpness.push_back(v.sharpness);
  }
  d["edges"] = make_array<std::int32_t>(sharp.edges.size(), 2, [&](std::int32_t* out) { std::copy(ends.begin(), ends.end(), out); });
  d["edge_sharpness"] = array_of<double>(edge_sharpness.size(), 1, edge_sharpness.data());
  d["vertices"] = array_of<std::int32_t>(vertices.size(), 1, vertices.data());
  d["vertex_sharpness"] = array_of<double>(vertex_sharpness.size(), 1, vertex_sharpness.data());
  d["method"] = to_string(sharp.method);
  return d;
}

RgbMesh mesh_from_arrays(const DoubleArray& points, const IndexArray& triangles, const std::string& what,
                         const SharpFeatures& sharp) {
  const std::string prefix = what.empty() ? "" : what + " ";
  const std::vector<Vec3> p = points_of_array(points, (prefix + "points").c_str());
  require_rows_of_three(triangles, (prefix + "triangles").c_str());
  const std::size_t n = p.size(), m = static_cast<std::size_t>(triangles.shape(0));
  std::vector<std::array<std::int32_t, 3>> t(m);
  const std::int64_t* c = triangles.data();
  for (std::size_t i = 0; i < m; ++i)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = c[3 * i + static_cast<std::size_t>(k)];
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw InputError(prefix + "triangles: triangle " + std::to_string(i) + " has vertex index " + std::to_string(v) +
                         ", out of range (there are " + std::to_string(n) + " points)");
      t[i][static_cast<std::size_t>(k)] = static_cast<std::int32_t>(v);
    }
  return RgbMesh::from_triangles(p, t, sharp);
}

void bind_mesh(py::module_& m) {
  py::class_<RgbMesh>(m, "Mesh", "An RGB subdivision mesh: its base mesh and the vertices inserted since.")
      .def_static(
          "from_arrays",
          [](const DoubleArray& p, const IndexArray& t, const py::object& sharp_edges, const py::object& edge_sharpness,
             const py::object& sharp_vertices, const py::object& vertex_sharpness, const std::string& crease_method,
             const py::object& sharp_angle) {
            SharpFeatures sharp =
                sharp_features_of(sharp_edges, edge_sharpness, sharp_vertices, vertex_sharpness, crease_method);
            if (!sharp_angle.is_none()) {
              // Checked as the mesh itself is, then the angle's creases under the given ones.
              const RgbMesh plain = mesh_from_arrays(p, t);
              std::vector<Vec3> points(plain.num_base_vertices());
              for (std::size_t i = 0; i < points.size(); ++i)
                points[i] = plain.insertion_point(VertexHandle(static_cast<std::int32_t>(i)));
              const double angle = py::cast<double>(sharp_angle);
              if (!(angle > 0.0 && angle < 180.0)) throw InputError("sharp_angle: degrees in (0, 180)");
              sharp = merged(sharp, detect_sharp_features(points, plain.base_triangles(), angle));
            }
            return mesh_from_arrays(p, t, "", sharp);
          },
          py::arg("points"), py::arg("triangles"), py::kw_only(), py::arg("sharp_edges") = py::none(),
          py::arg("edge_sharpness") = py::none(), py::arg("sharp_vertices") = py::none(),
          py::arg("vertex_sharpness") = py::none(), py::arg("crease_method") = "uniform",
          py::arg("sharp_angle") = py::none(),
          "A base mesh from an (n, 3) float array of points and an (m, 3) integer array of "
          "counter-clockwise triangles, validated as the mesh files are (ValueError naming the element). "
          "Sharp features (creases and corners, as OpenSubdiv's): sharp_edges (k, 2) vertex indices with "
          "edge_sharpness (k,) (0 smooth, 10 infinitely sharp, between: semi-sharp; default 10), sharp_vertices "
          "(j,) with vertex_sharpness (j,), crease_method 'uniform' or 'chaikin'; sharp_angle: also every edge "
          "whose triangles' normals differ by more than this many degrees (the given ones win).")
      .def(
          "sharp_features", [](const RgbMesh& mesh) { return sharp_features_dict(mesh.sharp_features()); },
          "The base mesh's sharp features: {'edges': (k, 2) base vertex indices, 'edge_sharpness': (k,), "
          "'vertices': (j,), 'vertex_sharpness': (j,), 'method': 'uniform' or 'chaikin'} (empty arrays without any).")
      .def(
          "vertex_rules",
          [](const RgbMesh& mesh) {
            return per_vertex<std::uint8_t, 1>(mesh, [&](VertexHandle v, std::uint8_t* d) {
              *d = static_cast<std::uint8_t>(mesh.vertex_rule(v));
            });
          },
          "Each vertex's subdivision rule at its shown level: 0 smooth, 1 dart, 2 crease, 3 corner (boundary "
          "vertices are creases or corners).")
      .def(
          "edges",
          [](const RgbMesh& mesh) {
            const std::vector<std::int32_t> row = rows_of_slots(mesh);
            std::vector<std::int32_t> ends;
            std::vector<double> sharpness;
            ends.reserve(2 * mesh.num_edges());
            sharpness.reserve(mesh.num_edges());
            for (const EdgeHandle e : mesh.edges()) {
              for (const VertexHandle v : mesh.edge_vertices(e)) ends.push_back(row[static_cast<std::size_t>(v.idx)]);
              sharpness.push_back(mesh.sharpness(e));
            }
            return py::make_tuple(
                make_array<std::int32_t>(mesh.num_edges(), 2, [&](std::int32_t* d) { std::copy(ends.begin(), ends.end(), d); }),
                array_of<double>(sharpness.size(), 1, sharpness.data()));
          },
          "The edges as (rows (k, 2) of the point arrays, sharpness (k,)): each edge's sharpness at its level, "
          "10 on the boundary, 0 where smooth.")
      .def_property_readonly("num_vertices", &RgbMesh::num_vertices)
      .def_property_readonly("num_triangles", &RgbMesh::num_triangles)
      .def_property_readonly("max_level", &RgbMesh::max_level)
      .def(
          "control_points",
          [](const RgbMesh& mesh) {
            // A vertex shown above its insertion level has its control point from its limit
            // position (p^k = g p^l + (1 - g) p^∞, Eq. 6): those limits first, and only those
            // (in a uniform mesh a quarter of the vertices; computing every limit costs four
            // times as much), here, since computing one fills a cache.
            const std::vector<std::uint8_t> shown = mesh.shown_levels();
            {
              py::gil_scoped_release release;
              for (const VertexHandle v : mesh.vertices())
                if (shown[static_cast<std::size_t>(v.idx)] > mesh.level(v)) mesh.limit_position(v);
            }
            return per_vertex<double, 3>(
                mesh, [&](VertexHandle v, double* d) { put(mesh.control_point(v, shown[static_cast<std::size_t>(v.idx)]), d); });
          },
          "The vertices' control points at their shown level (where they are in the current mesh), (n, 3): the "
          "rows of the point arrays, which triangles() indexes.")
      .def(
          "insertion_points",
          [](const RgbMesh& mesh) {
            return per_vertex<double, 3>(mesh, [&](VertexHandle v, double* d) { put(mesh.insertion_point(v), d); });
          },
          "The vertices' control points at their insertion level (the base points for base vertices; Loop's "
          "odd rule for the others), (n, 3): stored, so a plain copy.")
      .def(
          "limit_positions",
          [](RgbMesh& mesh) {
            {
              py::gil_scoped_release release;
              mesh.compute_limits();
            }
            return per_vertex<double, 3>(mesh, [&](VertexHandle v, double* d) { put(mesh.limit_position(v), d); });
          },
          "The vertices' positions on the Loop limit surface, (n, 3), rows of the point arrays. Computed once "
          "(RgbMesh::compute_limits, which may insert and remove helper vertices: the mesh is the same, but the "
          "rows of the per-triangle arrays may come in another order afterwards).")
      .def(
          "triangles",
          [](const RgbMesh& mesh) {
            // Without free vertex slots (a mesh never coarsened) a vertex's row is its slot.
            if (static_cast<std::size_t>(mesh.vertex_slots()) == mesh.num_vertices())
              return per_triangle<std::int32_t, 3>(mesh, [&](TriangleHandle t, std::int32_t* d) {
                const auto c = mesh.triangle_vertices(t);
                for (std::size_t k = 0; k < 3; ++k) d[k] = c[k].idx;
              });
            const std::vector<std::int32_t> row = rows_of_slots(mesh);
            return per_triangle<std::int32_t, 3>(mesh, [&](TriangleHandle t, std::int32_t* d) {
              const auto c = mesh.triangle_vertices(t);
              for (std::size_t k = 0; k < 3; ++k) d[k] = row[static_cast<std::size_t>(c[k].idx)];
            });
          },
          "The triangles, (m, 3) indices into the point arrays, counter-clockwise.")
      .def(
          "vertex_levels",
          [](const RgbMesh& mesh) {
            return per_vertex<std::uint8_t, 1>(mesh, [&](VertexHandle v, std::uint8_t* d) { *d = static_cast<std::uint8_t>(mesh.level(v)); });
          },
          "Each vertex's insertion level (0: a base vertex).")
      .def(
          "triangle_levels",
          [](const RgbMesh& mesh) {
            return per_triangle<std::uint8_t, 1>(mesh, [&](TriangleHandle t, std::uint8_t* d) { *d = static_cast<std::uint8_t>(mesh.level(t)); });
          },
          "Each triangle's level, in the order of triangles().")
      .def(
          "triangle_colors",
          [](const RgbMesh& mesh) {
            return per_triangle<std::uint8_t, 1>(mesh, [&](TriangleHandle t, std::uint8_t* d) { *d = static_cast<std::uint8_t>(mesh.color(t)); });
          },
          "Each triangle's colour: 0 green, 1 red, 2 blue (the paper's section IV).")
      .def(
          "parents",
          [](const RgbMesh& mesh) {
            const std::vector<std::int32_t> row = rows_of_slots(mesh);
            return per_vertex<std::int32_t, 2>(mesh, [&](VertexHandle v, std::int32_t* d) {
              const bool base = mesh.level(v) == 0;
              for (std::size_t k = 0; k < 2; ++k) d[k] = base ? -1 : row[static_cast<std::size_t>(mesh.parents(v)[k].idx)];
            });
          },
          "Each vertex's parents, (n, 2) rows of the point arrays: the ends of the edge it split (its "
          "control point is the Loop edge rule's there); -1, -1 for a base vertex.")
      .def(
          "refine_uniform",
          [](RgbMesh& mesh, int level) {
            if (level < 0 || level > kMaxLevel)
              throw InputError("level " + std::to_string(level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
            const RefinementOptions o = interruptible(kMaxLevel);
            py::gil_scoped_release release;
            const RefinementResult r = selective_refinement(mesh, UniformLevel(level), o);
            return r.splits;
          },
          py::arg("level"), "Refines (or coarsens) to the uniform mesh of this level; returns the vertices inserted. Ctrl-C "
          "interrupts, leaving a valid mesh: between two levels when refining a uniform mesh (each level "
          "is a few passes over the arrays, on every core), between two operations otherwise.")
      .def("refine", &refine, py::kw_only(), py::arg("uniform") = py::none(), py::arg("at_least") = py::none(),
           py::arg("ball") = py::none(), py::arg("max_edge") = py::none(), py::arg("tolerance") = py::none(),
           py::arg("budget") = py::none(), py::arg("max_level") = kMaxLevel,
           "Selective refinement by the built-in criteria, applied in this order: uniform level, at least a "
           "level, a ball (x, y, z, radius, level), a longest edge, a geometric tolerance, a triangle budget; "
           "no vertex above max_level. Returns {'splits', 'removals'}. Ctrl-C interrupts, leaving a valid mesh.")
      .def("adapt_to", &adapt_to, py::kw_only(), py::arg("triangle_values") = py::none(), py::arg("refine_above") = 0.5,
           py::arg("vertex_values") = py::none(), py::arg("coarsen_below") = 0.0, py::arg("max_level") = kMaxLevel,
           "Refines the triangles whose value (one per row of triangles()) is above refine_above one level, and "
           "removes the vertices whose value (one per point) is below coarsen_below where the RGB rules allow.")
      .def("validate", [](const RgbMesh& mesh) { return mesh.validate(); },
           "'' when every invariant holds (conformity, manifoldness, orientation, colours, levels), else the first violation.");
}

}  // namespace rgbmesh::python
