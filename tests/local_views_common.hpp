#pragma once
// Shared by test_local_views (processes simulated in one) and mpi_local_views_check (under
// mpirun): an adaptive start mesh, marks across its parts, the whole mesh refined with them,
// each process's local view refined with the marks it sees, and the comparison inside a part.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <unordered_set>
#include <vector>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/parallel/local_view.hpp"
#include "rgbmesh/parallel/partition.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

namespace rgbmesh::parallel::testing {

// Refines the triangles marked by their corners' start slots.
inline void refine_marked(RgbMesh& m, const std::set<std::array<std::int32_t, 3>>& marked) {
  std::vector<double> values(static_cast<std::size_t>(m.triangle_slots()), 0.0);
  for (const TriangleHandle t : m.triangles()) {
    std::array<std::int32_t, 3> c{};
    const auto v = m.triangle_vertices(t);
    for (int i = 0; i < 3; ++i) c[i] = v[i].idx;
    std::sort(c.begin(), c.end());
    if (marked.count(c)) values[static_cast<std::size_t>(t.idx)] = 1.0;
  }
  selective_refinement(m, FieldCriterion(std::move(values), 0.5, {}, 0.0));
  canonical_diagonals(m);  // as adapt does after each adaptation
}

// The triangles with all three corners in a region, by their corners' keys.
inline std::set<std::array<VertexKey, 3>> triangles_in(const RgbMesh& m, const VertexKeys& k,
                                                       const std::unordered_set<VertexKey>& region) {
  std::set<std::array<VertexKey, 3>> out;
  for (const TriangleHandle t : m.triangles()) {
    std::array<VertexKey, 3> c{};
    const auto v = m.triangle_vertices(t);
    bool inside = true;
    for (int i = 0; i < 3; ++i) {
      c[i] = k.of_slot.at(v[i].idx);
      inside = inside && region.count(c[i]);
    }
    if (!inside) continue;
    std::sort(c.begin(), c.end());
    out.insert(c);
  }
  return out;
}

// The start (adaptive sphere-peak above a floor at level 2), the marks (every triangle in a band
// across the sphere and along a great circle: they cross the parts' interfaces; by their
// corners' slots), the whole mesh refined with them, and its four parts.
struct Setup {
  static constexpr int kParts = 4;
  RgbMesh whole, refined;
  std::unordered_set<std::int32_t> start;
  std::set<std::array<std::int32_t, 3>> marked;
  VertexKeys refined_keys;
  Units units;
  Partition partition;
};
inline const Setup& setup() {
  static const Setup s = [] {
    Setup out;
    const TriangleMeshData ico = icosahedron();
    out.whole = RgbMesh::from_triangles(ico.points, ico.triangles);
    adapt::AdaptOptions o;
    o.projection = fem::Projection(fem::project_to_unit_sphere);
    o.min_level = 2;
    o.max_cycles = 40;
    o.max_dofs = 8000;
    adapt::run_cycles(out.whole, fem::sphere_peak(), o);
    out.start = vertex_slots_alive(out.whole);
    for (const TriangleHandle t : out.whole.triangles()) {
      const auto v = out.whole.triangle_vertices(t);
      const Vec3 c = (out.whole.control_point(v[0]) + out.whole.control_point(v[1]) + out.whole.control_point(v[2])) * (1.0 / 3);
      if (std::abs(c.y - 0.3) < 0.08 || std::abs(c.x + c.z) < 0.05) {
        std::array<std::int32_t, 3> k{v[0].idx, v[1].idx, v[2].idx};
        std::sort(k.begin(), k.end());
        out.marked.insert(k);
      }
    }
    out.refined = out.whole;
    refine_marked(out.refined, out.marked);
    out.refined_keys = vertex_keys(out.refined, out.start);
    out.units = units(out.whole, 2, Setup::kParts);
    out.partition = partition(out.units, Setup::kParts);
    return out;
  }();
  return s;
}

// Process q's view: its part and `ghost_layers` layers of the start mesh, refined with the
// marks on its own triangles (each process marks its own), or with `ghost_marks` also those on
// its ghost triangles (which it has as the whole mesh has them).
struct View {
  RgbMesh mesh;
  std::unordered_set<std::int32_t> start;  // its vertices before the refinement
  std::unordered_set<VertexKey> owned;     // its part's start vertices
  std::unordered_set<VertexKey> fine;      // and its ghost layers'
};
inline View refined_view(int q, int ghost_layers, bool ghost_marks = false) {
  const Setup& s = setup();
  View view;
  std::vector<char> keep(static_cast<std::size_t>(s.whole.triangle_slots()), 0);
  std::set<std::array<std::int32_t, 3>> own_triangles;
  for (const TriangleHandle t : s.whole.triangles())
    if (s.partition.part_of[static_cast<std::size_t>(s.units.of_triangle[t.idx])] == q) {
      keep[static_cast<std::size_t>(t.idx)] = 1;
      std::array<std::int32_t, 3> c{};
      const auto v = s.whole.triangle_vertices(t);
      for (int i = 0; i < 3; ++i) {
        view.owned.insert(static_cast<VertexKey>(v[i].idx));
        c[i] = v[i].idx;
      }
      std::sort(c.begin(), c.end());
      own_triangles.insert(c);
    }
  view.mesh = local_view(s.whole, keep, 2, ghost_layers);
  view.start = vertex_slots_alive(view.mesh);
  view.fine = view.owned;
  for (int layer = 0; layer < ghost_layers; ++layer) {
    std::unordered_set<VertexKey> next = view.fine;
    for (const TriangleHandle t : s.whole.triangles()) {
      bool touches = false;
      for (const VertexHandle v : s.whole.triangle_vertices(t)) touches = touches || view.fine.count(static_cast<VertexKey>(v.idx));
      if (touches)
        for (const VertexHandle v : s.whole.triangle_vertices(t)) next.insert(static_cast<VertexKey>(v.idx));
    }
    view.fine = std::move(next);
  }
  std::set<std::array<std::int32_t, 3>> visible;
  for (const auto& m : s.marked) {
    const bool in_fine = view.fine.count(static_cast<VertexKey>(m[0])) && view.fine.count(static_cast<VertexKey>(m[1])) &&
                         view.fine.count(static_cast<VertexKey>(m[2]));
    if (own_triangles.count(m) || (ghost_marks && in_fine)) visible.insert(m);
  }
  refine_marked(view.mesh, visible);
  return view;
}

// Inside the view's part: the triangles the whole mesh refined has there that the view lacks,
// those it has that the whole mesh does not, and how far its points are from the whole mesh's.
struct Compared {
  std::size_t missing = 0, extra = 0, inside = 0;
  std::size_t missing_vertices = 0;  // vertices of the whole mesh refined inside the part that the view lacks
  double moved = 0;
};
inline Compared compare_inside(const View& view) {
  const Setup& s = setup();
  Compared c;
  const VertexKeys k = vertex_keys(view.mesh, view.start);
  const std::unordered_set<VertexKey> mine = key_region(view.owned, s.refined_keys);
  const auto expected = triangles_in(s.refined, s.refined_keys, mine);
  const auto got = triangles_in(view.mesh, k, mine);
  c.inside = expected.size();
  for (const auto& t : expected) c.missing += got.count(t) == 0;
  for (const auto& t : got) c.extra += expected.count(t) == 0;
  for (const VertexKey key : mine) {
    if (!k.vertex.count(key)) {
      ++c.missing_vertices;
      continue;
    }
    c.moved = std::max(c.moved, norm(view.mesh.control_point(k.vertex.at(key)) -
                                     s.refined.control_point(s.refined_keys.vertex.at(key))));
  }
  return c;
}

}  // namespace rgbmesh::parallel::testing
