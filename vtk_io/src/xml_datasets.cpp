// The arrays of the VTK XML files (xml_datasets.hpp).

#include <algorithm>
#include "xml_datasets.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>

#include "rgb_state_io.hpp"

namespace rgbmesh::detail {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>,
              "Vec3 must be three packed doubles to be written as a Float64 array");
static_assert(sizeof(std::array<std::int32_t, 3>) == 3 * sizeof(std::int32_t),
              "a triangle must be three packed int32 to be written as connectivity");
static_assert(sizeof(Color) == 1, "Color must be one byte to be written as a UInt8 array");

// An array of `tuples` tuples computed one at a time: value(i, out) writes tuple i.
template <class T, class Value>
XmlArray computed_array(std::string name, XmlType type, int components, std::size_t tuples, Value value) {
  return XmlArray{std::move(name), type, components, tuples, [value, components](std::size_t first, std::size_t count, void* out) {
                    T* o = static_cast<T*>(out);
                    for (std::size_t i = 0; i < count; ++i, o += components) value(first + i, o);
                  }};
}

XmlArray state_version_array(std::int32_t version) {
  return computed_array<std::int32_t>(kStateVersionArray, XmlType::int32, 1, 1,
                                      [version](std::size_t, std::int32_t* out) { *out = version; });
}

XmlArray base_triangles_array(const std::vector<std::array<std::int32_t, 3>>& triangles) {
  return borrowed_array(kBaseTrianglesArray, XmlType::int32, 3, triangles.size(),
                        triangles.empty() ? nullptr : triangles.front().data());
}

// Version 2's sharp features (rgb_state_io.hpp); `sharp` must outlive the writing.
void add_sharp_arrays(std::vector<XmlArray>& field, const SharpFeatures& sharp) {
  if (sharp.empty()) return;
  const std::vector<SharpEdge>& e = sharp.edges;
  const std::vector<SharpVertex>& v = sharp.vertices;
  if (!e.empty()) {
    field.push_back(computed_array<std::int32_t>(kSharpEdgesArray, XmlType::int32, 2, e.size(),
                                                 [&e](std::size_t i, std::int32_t* out) {
                                                   out[0] = e[i].a;
                                                   out[1] = e[i].b;
                                                 }));
    field.push_back(computed_array<double>(kSharpEdgeSharpnessArray, XmlType::float64, 1, e.size(),
                                           [&e](std::size_t i, double* out) { *out = e[i].sharpness; }));
  }
  if (!v.empty()) {
    field.push_back(computed_array<std::int32_t>(kSharpVerticesArray, XmlType::int32, 1, v.size(),
                                                 [&v](std::size_t i, std::int32_t* out) { *out = v[i].v; }));
    field.push_back(computed_array<double>(kSharpVertexSharpnessArray, XmlType::float64, 1, v.size(),
                                           [&v](std::size_t i, double* out) { *out = v[i].sharpness; }));
  }
  const std::int32_t method = sharp.method == CreaseMethod::chaikin ? 1 : 0;
  field.push_back(computed_array<std::int32_t>(kCreaseMethodArray, XmlType::int32, 1, 1,
                                               [method](std::size_t, std::int32_t* out) { *out = method; }));
}

}  // namespace

XmlDataSet snapshot_data_set(const MeshSnapshot& mesh, bool unstructured) {
  XmlDataSet d;
  d.kind = unstructured ? XmlDataSet::Kind::grid_triangles : XmlDataSet::Kind::poly_triangles;
  d.points = mesh.points.size();
  d.cells = mesh.triangles.size();
  d.coordinates = borrowed_array("Points", XmlType::float64, 3, d.points, mesh.points.data());
  d.connectivity = borrowed_array("connectivity", XmlType::int32, 1, 3 * d.cells,
                                  mesh.triangles.empty() ? nullptr : mesh.triangles.front().data());
  if (!mesh.vertex_level.empty())
    d.point_data.push_back(borrowed_array("level", XmlType::uint8, 1, d.points, mesh.vertex_level.data()));
  if (!mesh.vertex_rule.empty())
    d.point_data.push_back(borrowed_array("vertex_rule", XmlType::uint8, 1, d.points, mesh.vertex_rule.data()));
  for (const NamedArray& a : mesh.point_data) {
    const void* values = a.same_as_points ? static_cast<const void*>(mesh.points.data()) : a.values.data();
    d.point_data.push_back(borrowed_array(a.name, XmlType::float64, a.components, d.points, values));
  }
  if (mesh.state) {
    const RgbState& s = *mesh.state;
    if (s.base_vertex.size() != d.points || s.parents.size() != d.points)
      throw std::invalid_argument("the RGB state does not have one entry per point");
    d.point_data.push_back(borrowed_array(kBaseVertexArray, XmlType::int32, 1, d.points, s.base_vertex.data()));
    d.point_data.push_back(
        borrowed_array(kParentsArray, XmlType::int32, 2, d.points, s.parents.empty() ? nullptr : s.parents.front().data()));
    d.field_data.push_back(state_version_array(s.version));
    d.field_data.push_back(borrowed_array(kBasePointsArray, XmlType::float64, 3, s.base_points.size(), s.base_points.data()));
    d.field_data.push_back(base_triangles_array(s.base_triangles));
    add_sharp_arrays(d.field_data, s.sharp);
  }
  if (mesh.piece_state) {
    const RgbState& s = *mesh.piece_state;
    if (s.base_vertex.size() != s.parents.size() || s.parents.size() < d.points)
      throw std::invalid_argument("a piece's RGB state does not have an entry per point and per ancestor");
    d.field_data.push_back(state_version_array(s.version));
    d.field_data.push_back(
        borrowed_array(kBasePointsArray, XmlType::float64, 3, s.base_points.size(), s.base_points.data()));
    d.field_data.push_back(base_triangles_array(s.base_triangles));
    add_sharp_arrays(d.field_data, s.sharp);
    d.field_data.push_back(
        borrowed_array(kPieceBaseVertexArray, XmlType::int32, 1, s.base_vertex.size(), s.base_vertex.data()));
    d.field_data.push_back(borrowed_array(kPieceParentsArray, XmlType::int32, 2, s.parents.size(),
                                          s.parents.empty() ? nullptr : s.parents.front().data()));
  }
  if (!mesh.triangle_level.empty())
    d.cell_data.push_back(borrowed_array("level", XmlType::uint8, 1, d.cells, mesh.triangle_level.data()));
  if (!mesh.triangle_color.empty())
    d.cell_data.push_back(borrowed_array("color", XmlType::uint8, 1, d.cells, mesh.triangle_color.data()));
  for (const NamedArray& a : mesh.cell_data)
    d.cell_data.push_back(borrowed_array(a.name, XmlType::float64, a.components, d.cells, a.values.data()));
  return d;
}

XmlDataSet point_cloud_data_set(const std::vector<Vec3>& points, const std::vector<NamedArray>& point_data) {
  XmlDataSet d;
  d.kind = XmlDataSet::Kind::poly_vertices;
  d.points = d.cells = points.size();
  d.coordinates = borrowed_array("Points", XmlType::float64, 3, d.points, points.data());
  d.connectivity = computed_array<std::int32_t>("connectivity", XmlType::int32, 1, d.cells,
                                                [](std::size_t i, std::int32_t* out) { *out = static_cast<std::int32_t>(i); });
  for (const NamedArray& a : point_data)
    d.point_data.push_back(borrowed_array(a.name, XmlType::float64, a.components, d.points, a.values.data()));
  return d;
}

MeshDataSet::MeshDataSet(const RgbMesh& mesh, bool unstructured, bool limit_points)
    : mesh_(mesh), shown_(mesh.shown_levels()) {
  if (mesh.base_triangles().empty())
    throw std::invalid_argument("save_state: the mesh was not made by RgbMesh::from_triangles");
  const std::size_t n = mesh.num_vertices(), m = mesh.num_triangles();
  // Points and cells are numbered as their slots where the live ones are the first slots (free
  // slots only at the end, as compute_limits' helpers leave them): no maps, which would take
  // 20 bytes per vertex at the peak of a large write.
  const bool vertices_first = std::all_of(mesh.vertices().begin(), mesh.vertices().end(),
                                          [n](VertexHandle v) { return static_cast<std::size_t>(v.idx) < n; });
  const bool triangles_first = std::all_of(mesh.triangles().begin(), mesh.triangles().end(),
                                           [m](TriangleHandle t) { return static_cast<std::size_t>(t.idx) < m; });
  if (!vertices_first) {
    point_of_slot_.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
    vertex_slot_.reserve(n);
    for (const VertexHandle v : mesh.vertices()) {
      point_of_slot_[static_cast<std::size_t>(v.idx)] = static_cast<std::int32_t>(vertex_slot_.size());
      vertex_slot_.push_back(v.idx);
    }
  }
  if (!triangles_first) {
    cell_checkpoint_.reserve(m / kCellStride + 1);
    std::size_t cell = 0;
    for (const TriangleHandle t : mesh.triangles())
      if (cell++ % kCellStride == 0) cell_checkpoint_.push_back(t.idx);
  }

  XmlDataSet& d = data_;
  d.kind = unstructured ? XmlDataSet::Kind::grid_triangles : XmlDataSet::Kind::poly_triangles;
  d.points = n;
  d.cells = m;
  const auto point_array = [&](std::string name, auto value) {
    return computed_array<double>(std::move(name), XmlType::float64, 3, n, [this, value](std::size_t i, double* out) {
      const Vec3 p = value(i);
      out[0] = p.x;
      out[1] = p.y;
      out[2] = p.z;
    });
  };
  const auto shown = [this](std::size_t i) { return shown_point(i); };
  const auto limit = [this](std::size_t i) { return mesh_.limit_position(vertex(i)); };
  d.coordinates = limit_points ? point_array("Points", limit) : point_array("Points", shown);
  d.connectivity = XmlArray{"connectivity", XmlType::int32, 1, 3 * m, [this](std::size_t first, std::size_t count, void* out) {
                              // A block may start or end inside a triangle: the writer's blocks
                              // hold whole tuples of one value.
                              auto* o = static_cast<std::int32_t*>(out);
                              const std::size_t end = first + count, cells = (end + 2) / 3 - first / 3;
                              std::size_t i = first;
                              for_cells(first / 3, cells, [&](TriangleHandle t) {
                                const auto corners = mesh_.triangle_vertices(t);
                                for (std::size_t k = i % 3; k < 3 && i < end; ++k, ++i) *o++ = point(corners[k]);
                              });
                            }};

  d.point_data.push_back(computed_array<std::uint8_t>(
      "level", XmlType::uint8, 1, n,
      [this](std::size_t i, std::uint8_t* out) { *out = static_cast<std::uint8_t>(mesh_.level(vertex(i))); }));
  if (mesh.has_sharp_features())
    d.point_data.push_back(computed_array<std::uint8_t>("vertex_rule", XmlType::uint8, 1, n, [this](std::size_t i, std::uint8_t* out) {
      const VertexHandle v = vertex(i);
      *out = static_cast<std::uint8_t>(mesh_.vertex_rule(v, shown_[static_cast<std::size_t>(v.idx)]));
    }));
  d.point_data.push_back(point_array("control_point", shown));
  d.point_data.push_back(point_array("limit", limit));
  d.point_data.push_back(computed_array<std::int32_t>(kBaseVertexArray, XmlType::int32, 1, n, [this](std::size_t i, std::int32_t* out) {
    const VertexHandle v = vertex(i);
    *out = mesh_.level(v) == 0 ? v.idx : -1;  // base vertices keep the slots from_triangles gave them
  }));
  d.point_data.push_back(computed_array<std::int32_t>(kParentsArray, XmlType::int32, 2, n, [this](std::size_t i, std::int32_t* out) {
    const VertexHandle v = vertex(i);
    if (mesh_.level(v) == 0) {
      out[0] = out[1] = -1;
    } else {
      const auto& p = mesh_.parents(v);
      out[0] = point(p[0]);
      out[1] = point(p[1]);
    }
  }));
  d.field_data.push_back(state_version_array(RgbState::version_for(mesh.sharp_features())));
  d.field_data.push_back(
      computed_array<double>(kBasePointsArray, XmlType::float64, 3, mesh.num_base_vertices(), [this](std::size_t b, double* out) {
        const Vec3 p = mesh_.insertion_point(VertexHandle(static_cast<std::int32_t>(b)));
        out[0] = p.x;
        out[1] = p.y;
        out[2] = p.z;
      }));
  d.field_data.push_back(base_triangles_array(mesh.base_triangles()));
  add_sharp_arrays(d.field_data, mesh.sharp_features());
  d.cell_data.push_back(XmlArray{"level", XmlType::uint8, 1, m, [this](std::size_t first, std::size_t count, void* out) {
    auto* o = static_cast<std::uint8_t*>(out);
    for_cells(first, count, [&](TriangleHandle t) { *o++ = static_cast<std::uint8_t>(mesh_.level(t)); });
  }});
  d.cell_data.push_back(XmlArray{"color", XmlType::uint8, 1, m, [this](std::size_t first, std::size_t count, void* out) {
    auto* o = static_cast<std::uint8_t*>(out);
    for_cells(first, count, [&](TriangleHandle t) { *o++ = static_cast<std::uint8_t>(mesh_.color(t)); });
  }});
}

Vec3 MeshDataSet::shown_point(std::size_t point) const {
  const VertexHandle v = vertex(point);
  return mesh_.control_point(v, shown_[static_cast<std::size_t>(v.idx)]);
}

}  // namespace rgbmesh::detail
