#include "test_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "rgbmesh/geometry.hpp"

namespace rgbmesh::testing {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

BaseMesh single_triangle() { return {"single_triangle", {{0, 0, 0}, {1, 0, 0}, {0.5, 0.8, 0}}, {{0, 1, 2}}}; }

BaseMesh diamond() {
  return {"diamond", {{0, 0, 0}, {1, 0, 0}, {0.5, 0.8, 0}, {0.5, -0.8, 0}}, {{0, 1, 2}, {1, 0, 3}}};
}

BaseMesh tetrahedron() {
  return {"tetrahedron",
          {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
          {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}}};
}

BaseMesh octahedron() {
  return {"octahedron",
          {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
          {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}};
}

BaseMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  BaseMesh m{"icosahedron",
             {{-1, t, 0},
              {1, t, 0},
              {-1, -t, 0},
              {1, -t, 0},
              {0, -1, t},
              {0, 1, t},
              {0, -1, -t},
              {0, 1, -t},
              {t, 0, -1},
              {t, 0, 1},
              {-t, 0, -1},
              {-t, 0, 1}},
             {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
              {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}}};
  return m;
}

BaseMesh cube() {
  BaseMesh m{"cube", {}, {}};
  for (int i = 0; i < 8; ++i) m.points.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Faces as quads (outward, counter-clockwise), each split along one diagonal.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

BaseMesh bipyramid(int n) {
  BaseMesh m{"bipyramid" + std::to_string(n), {}, {}};
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    m.points.push_back({std::cos(a), std::sin(a), 0.1 * ((i % 3) - 1)});
  }
  const int top = n, bottom = n + 1;
  m.points.push_back({0, 0, 1});
  m.points.push_back({0, 0, -1});
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, top});
    m.triangles.push_back({j, i, bottom});
  }
  return m;
}

BaseMesh torus(int rings, int sides) {
  BaseMesh m{"torus", {}, {}};
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < sides; ++j) {
      const double u = 2 * kPi * i / rings, v = 2 * kPi * j / sides;
      m.points.push_back(
          {(2 + 0.7 * std::cos(v)) * std::cos(u), (2 + 0.7 * std::cos(v)) * std::sin(u), 0.7 * std::sin(v)});
    }
  }
  auto id = [&](int i, int j) { return ((i + rings) % rings) * sides + (j + sides) % sides; };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < sides; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

BaseMesh grid_with_holes(int n, int holes) {
  BaseMesh m{"grid_with_holes", {}, {}};
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.points.push_back({double(i), double(j), 0.05 * ((i * 7 + j * 3) % 5)});
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  // Holes: single missing quads on the diagonal, spaced so that they do not touch each other
  // or the outer boundary (each adds one boundary loop).
  auto is_hole = [&](int i, int j) {
    for (int h = 0; h < holes; ++h) {
      const int c = 1 + 2 * h;
      if (i == c && j == c) return true;
    }
    return false;
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (is_hole(i, j)) continue;
      // Alternate diagonals so that vertex valences vary.
      if ((i + j) % 2 == 0) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        m.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  }
  // Drop vertices no triangle uses (none here, the holes are single quads).
  return m;
}

BaseMesh fan_disk(int n) {
  BaseMesh m{"fan_disk" + std::to_string(n), {{0, 0, 0.3}}, {}};
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    m.points.push_back({std::cos(a), std::sin(a), 0});
  }
  for (int i = 0; i < n; ++i) m.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
  return m;
}

BaseMesh cad_pillbox(int n, double height) {
  BaseMesh m{"cad_pillbox" + std::to_string(n), {}, {}};
  for (const double z : {0.0, height})
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      m.points.push_back({std::cos(a), std::sin(a), z});
    }
  for (int i = 0; i < n; ++i) {
    const int a = i, b = (i + 1) % n, c = n + (i + 1) % n, d = n + i;
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  }
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});          // the bottom, facing -z
    m.triangles.push_back({n, n + i, n + i + 1});  // the top, facing +z
  }
  return m;
}

BaseMesh double_torus() {
  // Two tori glued: remove one quad (two triangles) from each and connect the holes by a
  // tube of 4 quads.
  BaseMesh a = torus(8, 4);
  BaseMesh m{"double_torus", a.points, {}};
  const int na = static_cast<int>(a.points.size());
  for (const auto& p : a.points) m.points.push_back({p.x + 6.0, p.y, p.z});
  // The quad at ring 0, sides 0..1 in torus(8,4): triangles 0 and 1.
  for (std::size_t k = 2; k < a.triangles.size(); ++k) m.triangles.push_back(a.triangles[k]);
  // Second copy, mirrored in x so the holes face each other: flip orientation too. Remove the
  // quad at ring 4 (the side facing -x after mirroring... use ring 4 of the copy).
  const int sides = 4;
  for (auto& p : m.points) (void)p;
  for (int i = na; i < 2 * na; ++i) m.points[i].x = 6.0 - a.points[i - na].x;
  const std::size_t skip = 2 * (4 * sides);  // ring 4, side 0: triangles 32 and 33
  for (std::size_t k = 0; k < a.triangles.size(); ++k) {
    if (k == skip || k == skip + 1) continue;
    const auto& t = a.triangles[k];
    m.triangles.push_back({t[0] + na, t[2] + na, t[1] + na});  // mirrored: reverse orientation
  }
  // Hole 1: loop id(0,0), id(1,0), id(1,1), id(0,1) of the first torus.
  auto id = [&](int i, int j) { return ((i + 8) % 8) * sides + (j + sides) % sides; };
  const int h1[4] = {id(0, 0), id(1, 0), id(1, 1), id(0, 1)};
  const int h2[4] = {na + id(4, 0), na + id(5, 0), na + id(5, 1), na + id(4, 1)};
  // The hole boundary of torus 1 runs h1[0]->h1[3]->h1[2]->h1[1] along the remaining
  // triangles' free edges; connect with quads whose orientation matches both sides.
  for (int k = 0; k < 4; ++k) {
    const int a0 = h1[k], a1 = h1[(k + 1) % 4];
    const int b0 = h2[k], b1 = h2[(k + 1) % 4];
    m.triangles.push_back({a0, a1, b1});
    m.triangles.push_back({a0, b1, b0});
  }
  return m;
}

std::vector<BaseMesh> all_base_meshes() {
  return {single_triangle(), diamond(),     tetrahedron(), octahedron(),          icosahedron(), cube(),
          bipyramid(3),      bipyramid(12), torus(6, 5),   grid_with_holes(8, 3), fan_disk(3),   fan_disk(12),
          double_torus()};
}

std::vector<std::array<std::int32_t, 3>> canonical_triangles(const RgbMesh& m) {
  std::vector<std::array<std::int32_t, 3>> out;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    std::array<std::int32_t, 3> x{c[0].idx, c[1].idx, c[2].idx};
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    out.push_back(x);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::set<std::array<VertexName, 3>> named_triangles(const RgbMesh& m) {
  const std::vector<VertexName> name = vertex_names(m);
  std::set<std::array<VertexName, 3>> out;
  for (const TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    std::array<VertexName, 3> n{name[c[0].idx], name[c[1].idx], name[c[2].idx]};
    std::rotate(n.begin(), std::min_element(n.begin(), n.end()), n.end());
    out.insert(n);
  }
  return out;
}

// A cube of 12 triangles with every edge infinitely sharp (the 6 face diagonals smooth).
BaseMesh sharp_cube() {
  BaseMesh m = cube();
  m.name = "sharp_cube";
  const double diagonal = bounding_box_diagonal(m.points);
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      // Cube edges have length diagonal / sqrt(3); face diagonals are longer.
      if (a < b && std::abs(distance(m.points[a], m.points[b]) - diagonal / std::sqrt(3.0)) < 1e-9)
        m.sharp.edges.push_back({a, b, kInfiniteSharpness});
    }
  return m;
}

// An octahedron with one infinitely sharp edge: its ends are darts.
BaseMesh octahedron_with_darts() {
  BaseMesh m = octahedron();
  m.name = "octahedron_darts";
  m.sharp.edges.push_back({m.triangles[0][0], m.triangles[0][1], kInfiniteSharpness});
  return m;
}

// Semi-sharp creases of varying sharpness along a path with a corner, both methods.
BaseMesh graded_icosahedron(CreaseMethod method) {
  BaseMesh m = icosahedron();
  m.name = method == CreaseMethod::chaikin ? "graded_icosahedron_chaikin" : "graded_icosahedron";
  const float values[] = {0.4f, 1.0f, 1.7f, 2.5f, 3.3f, 10.0f};
  int k = 0;
  for (const auto& t : m.triangles) {
    if (k >= 6) break;
    m.sharp.edges.push_back({t[0], t[1], values[k++]});
  }
  m.sharp.vertices.push_back({m.triangles[7][2], 2.2f});
  m.sharp.method = method;
  return m;
}

}  // namespace rgbmesh::testing
