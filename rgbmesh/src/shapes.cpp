#include "rgbmesh/shapes.hpp"

#include <cmath>
#include <stdexcept>

namespace rgbmesh {

TriangleMeshData icosahedron() {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0, s = 1.0 / std::sqrt(1.0 + g * g);
  TriangleMeshData m;
  m.points = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
              {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3& p : m.points) p *= s;
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return m;
}

TriangleMeshData octahedron() {
  TriangleMeshData m;
  m.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

TriangleMeshData sharp_unit_cube() {
  TriangleMeshData m;
  // Vertex i at (i & 1, (i >> 1) & 1, (i >> 2) & 1).
  for (int i = 0; i < 8; ++i) m.points.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Each face counter-clockwise seen from outside, cut along its diagonal from its first corner.
  const std::int32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
    for (int k = 0; k < 4; ++k)
      if (f[k] < f[(k + 1) % 4]) m.sharp.edges.push_back({f[k], f[(k + 1) % 4], kInfiniteSharpness});
  }
  return m;
}

TriangleMeshData square_lattice(int cells, double side, int ghosts) {
  if (cells < 1 || cells > 4096 || ghosts < 0 || ghosts > 4096 || cells + 2 * ghosts > 4096 || !(side > 0) ||
      !std::isfinite(side))
    throw std::invalid_argument("square_lattice: cells in [1, 4096 - 2 ghosts], ghosts >= 0, side > 0");
  const int n = cells + 2 * ghosts;  // cells per side
  const double h = side / cells;
  TriangleMeshData m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.points.push_back({(i - ghosts) * h, (j - ghosts) * h, 0.0});
  const auto at = [n](int i, int j) { return static_cast<std::int32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

}  // namespace rgbmesh
