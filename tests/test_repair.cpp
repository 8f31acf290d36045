// rgbmesh::repair on small hand-built soups, through the reading path (prepare_triangle_mesh with
// SoupOptions::repair) as the tool uses it. Every result is checked against what the soup is
// known to be (counts, Euler characteristic, enclosed volume, area, positions), computed here
// from the triangles, not by the library.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/soup.hpp"

namespace {

using rgbmesh::InputError;
using rgbmesh::MeshDefectError;
using rgbmesh::PolygonSoup;
using rgbmesh::prepare_triangle_mesh;
using rgbmesh::SoupOptions;
using rgbmesh::TriangleMeshData;
using rgbmesh::Vec3;
using Face = std::vector<std::int64_t>;

SoupOptions repairing() { return rgbmesh::repair::soup_options(false, true); }

// The regular octahedron, counter-clockwise seen from outside: volume 4/3, area 4 sqrt(3).
PolygonSoup octahedron() {
  PolygonSoup s;
  s.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  s.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return s;
}

// The same faces, each with its own three vertices (as many exporters write them).
PolygonSoup apart(const PolygonSoup& joined) {
  PolygonSoup s;
  for (const Face& f : joined.faces) {
    Face own;
    for (const std::int64_t v : f) {
      own.push_back(static_cast<std::int64_t>(s.points.size()));
      s.points.push_back(joined.points[static_cast<std::size_t>(v)]);
    }
    s.faces.push_back(own);
  }
  return s;
}

// An axis-aligned box [x0, x1] x [0, 1] x [0, 1] as 12 outward triangles.
PolygonSoup box(double x0, double x1) {
  PolygonSoup s;
  for (int i = 0; i < 8; ++i) s.points.push_back({i & 1 ? x1 : x0, i & 2 ? 1.0 : 0.0, i & 4 ? 1.0 : 0.0});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.faces.push_back({q[0], q[1], q[2]});
    s.faces.push_back({q[0], q[2], q[3]});
  }
  return s;
}

// Counts of a triangle mesh, computed from its triangles.
struct Counts {
  std::size_t vertices = 0, edges = 0, triangles = 0, boundary_edges = 0, components = 0;
  long euler = 0;
  bool consistently_oriented = true;  // every directed edge at most once
  bool manifold_edges = true;         // no edge of more than two triangles
};

Counts counts_of(const TriangleMeshData& m) {
  Counts c;
  c.vertices = m.points.size();
  c.triangles = m.triangles.size();
  std::map<std::pair<int, int>, int> undirected, directed;
  std::vector<int> parent(m.points.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++undirected[{std::min(a, b), std::max(a, b)}];
      if (++directed[{a, b}] > 1) c.consistently_oriented = false;
      parent[find(a)] = find(b);
    }
  c.edges = undirected.size();
  for (const auto& [edge, n] : undirected) {
    c.boundary_edges += n == 1;
    if (n > 2) c.manifold_edges = false;
  }
  std::set<int> roots;
  for (std::size_t v = 0; v < m.points.size(); ++v) roots.insert(find(static_cast<int>(v)));
  c.components = roots.size();
  c.euler = static_cast<long>(c.vertices) - static_cast<long>(c.edges) + static_cast<long>(c.triangles);
  return c;
}

// The enclosed volume (divergence theorem; the sign says the orientation) and the area.
double volume_of(const TriangleMeshData& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += dot(m.points[t[0]], cross(m.points[t[1]], m.points[t[2]])) / 6;
  return v;
}
double area_of(const TriangleMeshData& m) {
  double a = 0;
  for (const auto& t : m.triangles)
    a += 0.5 * norm(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
  return a;
}

// The mesh passes the library's own construction and validation.
void expect_valid(const TriangleMeshData& m) {
  const rgbmesh::RgbMesh mesh = rgbmesh::RgbMesh::from_triangles(m.points, m.triangles);
  EXPECT_EQ(mesh.validate(), "");
}

std::string repair_note(const TriangleMeshData& m) {
  for (const std::string& note : m.notes)
    if (note.rfind("repaired: ", 0) == 0) return note;
  return "";
}

TEST(Repair, DuplicatePositionsBecomeOneSurface) {
  const PolygonSoup soup = apart(octahedron());  // 24 vertices at 6 positions
  const TriangleMeshData plain = prepare_triangle_mesh(soup);
  EXPECT_EQ(counts_of(plain).components, 8u);
  EXPECT_NE(std::find(plain.notes.begin(), plain.notes.end(),
                      "24 vertices at 6 positions: faces that meet only at equal positions are not joined "
                      "(--repair merges them)"),
            plain.notes.end());

  const TriangleMeshData m = prepare_triangle_mesh(soup, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 6u);
  EXPECT_EQ(c.triangles, 8u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.euler, 2);  // a sphere
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_NEAR(std::abs(volume_of(m)), 4.0 / 3, 1e-12);
  EXPECT_EQ(repair_note(m), "repaired: merged 18 duplicate vertices");
  expect_valid(m);
}

TEST(Repair, DuplicatePositionsOfATorusGiveGenusOne) {
  // A torus of 8 x 6 quads (96 triangles), every triangle with its own vertices.
  const int n = 8, k = 6;
  PolygonSoup joined;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / k;
      joined.points.push_back(
          {(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  const auto at = [&](int i, int j) { return static_cast<std::int64_t>(((i + n) % n) * k + (j + k) % k); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      joined.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      joined.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const TriangleMeshData m = prepare_triangle_mesh(apart(joined), repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 48u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.euler, 0);  // closed, one component: genus (2 - 0) / 2 = 1
  expect_valid(m);
}

// The octahedron with its edge (0, 2) split at its midpoint m on one side only (a T-junction)
// and the crack closed by the zero-area triangle (0, 2, m), as OpenSCAD exports do.
PolygonSoup t_junction() {
  PolygonSoup s = octahedron();
  s.points.push_back({0.5, 0.5, 0});  // m = 6
  s.faces[0] = {0, 6, 4};
  s.faces.push_back({6, 2, 4});
  s.faces.push_back({0, 2, 6});
  return s;
}

TEST(Repair, ZeroAreaTriangleIsCollapsedWithoutAHole) {
  const PolygonSoup soup = t_junction();
  try {
    prepare_triangle_mesh(soup);
    ADD_FAILURE() << "accepted a zero-area triangle";
  } catch (const MeshDefectError& e) {
    EXPECT_EQ(std::string(e.what()),
              "triangle 9 is degenerate: it has zero area (vertices 0, 2, 6 are collinear)");
    EXPECT_STREQ(e.hint(), "collapses degenerate triangles");
  }
  const TriangleMeshData m = prepare_triangle_mesh(soup, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.boundary_edges, 0u);  // closed stays closed
  EXPECT_EQ(c.euler, 2);
  EXPECT_EQ(c.components, 1u);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_NEAR(std::abs(volume_of(m)), 4.0 / 3, 1e-12);
  EXPECT_NEAR(area_of(m), 4 * std::sqrt(3.0), 1e-12);
  EXPECT_EQ(repair_note(m), "repaired: collapsed 1 zero-area triangle");
  expect_valid(m);

  // The same with a hole (the face opposite the T-junction removed): one boundary loop of 3 edges
  // before and after.
  PolygonSoup open = soup;
  open.faces.erase(open.faces.begin() + 6);  // (3, 1, 5)
  const TriangleMeshData o = prepare_triangle_mesh(open, repairing());
  EXPECT_EQ(counts_of(o).boundary_edges, 3u);
  EXPECT_EQ(counts_of(o).euler, 1);
  expect_valid(o);
}

TEST(Repair, NeedleIsCollapsedWithinTheBound) {
  // The octahedron's top vertex 4 doubled 1e-9 away (vertex 6), the gap closed by two needles.
  PolygonSoup s = octahedron();
  s.points.push_back({1e-9, 0, 1});
  s.faces[2] = {1, 3, 6};
  s.faces[3] = {3, 0, 6};
  s.faces.push_back({1, 6, 4});
  s.faces.push_back({0, 4, 6});
  EXPECT_EQ(prepare_triangle_mesh(s).triangles.size(), 10u);  // valid as it is: the needles have area
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 6u);
  EXPECT_EQ(c.triangles, 8u);
  EXPECT_EQ(c.euler, 2);
  EXPECT_EQ(c.boundary_edges, 0u);
  // Every vertex is one of the octahedron's, within the needle's short edge; the bound is 1e-6 of the
  // diagonal 2 sqrt(3).
  const PolygonSoup o = octahedron();
  for (const Vec3& p : m.points) {
    double nearest = 1;
    for (const Vec3& q : o.points) nearest = std::min(nearest, distance(p, q));
    EXPECT_LE(nearest, 1e-9);
  }
  EXPECT_EQ(repair_note(m).rfind(
                "repaired: collapsed 2 needle triangles (no point moved by more than 3.46e-06)", 0),
            0u)
      << repair_note(m);
  expect_valid(m);

  // A needle whose short edge is longer than the bound (1e-6 of the diagonal) is a shape, kept.
  s.points[6] = {1e-4, 0, 1};
  EXPECT_EQ(prepare_triangle_mesh(s, repairing()).triangles.size(), 10u);
}

TEST(Repair, PinchedVertexIsSplitIntoItsFans) {
  // Two tetrahedra touching at the origin only.
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  s.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
  EXPECT_THROW(prepare_triangle_mesh(s), MeshDefectError);
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 8u);
  EXPECT_EQ(c.components, 2u);  // the fans no longer share a vertex
  EXPECT_EQ(c.euler, 4);        // two spheres
  EXPECT_EQ(c.boundary_edges, 0u);
  std::size_t at_origin = 0;
  for (const Vec3& p : m.points) at_origin += p == Vec3(0, 0, 0);
  EXPECT_EQ(at_origin, 2u);
  EXPECT_EQ(repair_note(m), "repaired: split 1 non-manifold vertex into 2");
  expect_valid(m);
}

TEST(Repair, NonManifoldEdgeIsSplit) {
  // Three triangles on the edge (0, 1).
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_TRUE(c.manifold_edges);
  EXPECT_EQ(c.triangles, 3u);
  EXPECT_NE(repair_note(m).find("split 1 non-manifold edge"), std::string::npos) << repair_note(m);
  expect_valid(m);
}

TEST(Repair, BackToBackTrianglesBetweenTouchingPartsAreRemoved) {
  // Two unit boxes sharing the face x = 1: its two triangles appear in both, back to back.
  PolygonSoup s = box(0, 1);
  const PolygonSoup right = box(1, 2);
  const auto offset = static_cast<std::int64_t>(s.points.size());
  s.points.insert(s.points.end(), right.points.begin(), right.points.end());
  for (Face f : right.faces) {
    for (std::int64_t& v : f) v += offset;
    s.faces.push_back(f);
  }
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 12u);
  EXPECT_EQ(c.triangles, 20u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.euler, 2);
  EXPECT_NEAR(std::abs(volume_of(m)), 2.0, 1e-12);
  EXPECT_NE(repair_note(m).find("removed 2 back-to-back pairs of triangles"), std::string::npos)
      << repair_note(m);
  expect_valid(m);
}

TEST(Repair, TwoSidedSheetKeepsOneSide) {
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.faces = {{0, 1, 2}, {0, 2, 3}, {2, 1, 0}, {3, 2, 0}};
  EXPECT_THROW(prepare_triangle_mesh(s), MeshDefectError);
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.triangles, 2u);
  EXPECT_EQ(c.boundary_edges, 4u);
  EXPECT_NEAR(area_of(m), 1.0, 1e-15);
  expect_valid(m);
}

TEST(Repair, BackToBackZeroAreaPairIsRemoved) {
  // OpenSCAD's issue 1580 (testdata/scad/bugs/issue1580-back-to-back.scad): the tetrahedra
  // (1, 2, 3, 4) and (1, 2, 3, 5) on either side of the plane x = 0, with vertex 0 on their common
  // edge (1, 2), closed by a zero-area triangle (0, 1, 2) and its reverse.
  PolygonSoup s;
  s.points = {{0, 2, 0}, {0, 4, 0}, {0, 0, 0}, {0, 2, -4}, {2, 2, 0}, {-2, 2, 0}};
  s.faces = {{0, 1, 2}, {2, 1, 0}, {2, 0, 4}, {0, 1, 4}, {0, 5, 1},
             {0, 2, 5}, {2, 3, 5}, {4, 3, 2}, {1, 5, 3}, {4, 1, 3}};
  EXPECT_THROW(prepare_triangle_mesh(s), MeshDefectError);
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_EQ(c.vertices, 6u);
  EXPECT_EQ(c.triangles, 8u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.euler, 2);
  EXPECT_EQ(c.components, 1u);
  EXPECT_NEAR(std::abs(volume_of(m)), 2 * 16.0 / 3, 1e-12);  // two tetrahedra of volume 32 / 6
  EXPECT_EQ(repair_note(m), "repaired: collapsed 2 zero-area triangles");
  expect_valid(m);
}

TEST(Repair, InconsistentOrientationIsMadeConsistent) {
  PolygonSoup s = octahedron();
  for (const int f : {1, 4, 6}) std::reverse(s.faces[f].begin(), s.faces[f].end());
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  EXPECT_TRUE(counts_of(m).consistently_oriented);
  EXPECT_NEAR(std::abs(volume_of(m)), 4.0 / 3, 1e-12);
  EXPECT_EQ(repair_note(m), "repaired: re-oriented 3 triangles");
  expect_valid(m);
}

TEST(Repair, MoebiusStripIsCutOpen) {
  // 6 quads whose ends are glued with a half twist: not orientable.
  const int n = 6;
  PolygonSoup s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, half = a / 2;
    for (const double w : {-0.3, 0.3})
      s.points.push_back({(1 + w * std::cos(half)) * std::cos(a), (1 + w * std::cos(half)) * std::sin(a),
                          w * std::sin(half)});
  }
  for (int i = 0; i < n; ++i) {
    const std::int64_t a0 = 2 * i, a1 = 2 * i + 1;
    const std::int64_t b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    s.faces.push_back({a0, b0, b1});
    s.faces.push_back({a0, b1, a1});
  }
  EXPECT_THROW(prepare_triangle_mesh(s), MeshDefectError);
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  const Counts c = counts_of(m);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.triangles, 12u);
  EXPECT_EQ(c.euler, 1);  // the band (Euler characteristic 0) cut along one edge: a disk
  EXPECT_EQ(c.components, 1u);
  EXPECT_NE(repair_note(m).find("cut the surface open along 1 edge to orient it"), std::string::npos)
      << repair_note(m);
  expect_valid(m);
}

TEST(Repair, IsolatedVerticesAreDropped) {
  PolygonSoup s = octahedron();
  s.points.insert(s.points.begin(), {{5, 5, 5}, {6, 6, 6}});
  for (Face& f : s.faces)
    for (std::int64_t& v : f) v += 2;
  s.points.push_back({7, 7, 7});
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  EXPECT_EQ(m.points.size(), 6u);
  EXPECT_EQ(repair_note(m), "repaired: dropped 3 isolated vertices");
  expect_valid(m);
}

TEST(Repair, CoordinatesThatAreZeroButForRoundingAreSnapped) {
  // Vertex 4 at x = 1e-17 (a CAD tool's cos 90 degrees): set to 0, well within the bound.
  PolygonSoup s = octahedron();
  s.points[4].x = 1e-17;
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  for (const Vec3& p : m.points) EXPECT_TRUE(p.x == 0 || std::abs(p.x) == 1);
  EXPECT_EQ(repair_note(m).rfind("repaired: set 1 coordinate within 1e-12 of the diagonal to 0", 0), 0u);
}

TEST(Repair, CleanMeshIsUnchanged) {
  const PolygonSoup s = octahedron();
  const TriangleMeshData m = prepare_triangle_mesh(s, repairing());
  EXPECT_EQ(m.points, s.points);
  EXPECT_EQ(repair_note(m), "repaired: nothing needed repair");
  EXPECT_EQ(m.notes.size(), 1u);
}

TEST(Repair, WhatARepairCannotDoIsStillRefused) {
  // Non-finite coordinates are a broken file, not a defect.
  PolygonSoup s = octahedron();
  s.points[4].z = std::numeric_limits<double>::quiet_NaN();
  try {
    prepare_triangle_mesh(s, repairing());
    ADD_FAILURE() << "accepted NaN";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "vertex 4 has a non-finite coordinate (0, 0, nan)");
  }
  // Polygons need --triangulate, also with a repair.
  s = octahedron();
  s.faces.push_back({0, 1, 2, 3});
  try {
    prepare_triangle_mesh(s, repairing());
    ADD_FAILURE() << "accepted a quad";
  } catch (const InputError& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "face 8 has 4 vertices; only triangles are supported (use --triangulate to split polygons; a "
        "repair needs it too)");
  }
  // Nothing left: a lone zero-area triangle.
  s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  s.faces = {{0, 1, 2}};
  try {
    prepare_triangle_mesh(s, repairing());
    ADD_FAILURE() << "accepted a lone zero-area triangle";
  } catch (const MeshDefectError&) {
    ADD_FAILURE() << "a failed repair is no longer a defect to repair";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "could not be repaired: nothing is left of the mesh");
  }
}

TEST(Repair, ReportCountsWhatItDid) {
  // repair_triangles directly: the soup with every triangle apart and one face reversed.
  PolygonSoup s = apart(octahedron());
  std::reverse(s.faces[3].begin(), s.faces[3].end());
  std::vector<Vec3> points = s.points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  for (const Face& f : s.faces)
    triangles.push_back(
        {static_cast<std::int32_t>(f[0]), static_cast<std::int32_t>(f[1]), static_cast<std::int32_t>(f[2])});
  const rgbmesh::repair::RepairReport r = rgbmesh::repair::repair_triangles(points, triangles);
  EXPECT_EQ(r.merged_vertices, 18u);
  EXPECT_EQ(r.reoriented_triangles, 1u);
  EXPECT_EQ(points.size(), 6u);
  EXPECT_EQ(triangles.size(), 8u);
  EXPECT_NEAR(r.max_move, 1e-6 * 2 * std::sqrt(3.0), 1e-18);  // the bound: 1e-6 of the diagonal
}

}  // namespace
