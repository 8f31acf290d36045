// Sharp features from the geometry (sharpness.hpp): dihedral angles above a threshold make
// creases, creases that turn sharply make corners.

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/sharpness.hpp"

namespace rgbmesh {

SharpFeatures detect_sharp_features(const std::vector<Vec3>& points,
                                    const std::vector<std::array<std::int32_t, 3>>& triangles, double angle_degrees) {
  if (!(angle_degrees > 0.0 && angle_degrees < 180.0))
    throw std::invalid_argument("detect_sharp_features: the angle must be in (0, 180) degrees");
  const double cos_limit = std::cos(angle_degrees * loop::kPi / 180.0);
  // Each edge with its triangles' unit normals (one for a boundary edge).
  struct EdgeSides {
    Vec3 normal[2];
    int sides = 0;
  };
  std::map<std::pair<std::int32_t, std::int32_t>, EdgeSides> edges;
  for (const auto& t : triangles) {
    const Vec3 n = cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]);
    const double length = norm(n);
    const Vec3 unit = length > 0.0 ? n * (1.0 / length) : Vec3();
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      EdgeSides& e = edges[{std::min(a, b), std::max(a, b)}];
      if (e.sides < 2) e.normal[e.sides] = unit;
      ++e.sides;
    }
  }
  SharpFeatures out;
  // Per vertex, the other ends of its sharp edges (the boundary's included) for the corners.
  std::vector<std::vector<std::int32_t>> sharp_ends(points.size());
  for (const auto& [ends, e] : edges) {
    bool sharp = e.sides == 1;  // the boundary: sharp by Loop's rules, not tagged
    if (e.sides == 2 && dot(e.normal[0], e.normal[1]) < cos_limit) {
      out.edges.push_back({ends.first, ends.second, kInfiniteSharpness});
      sharp = true;
    }
    if (sharp) {
      sharp_ends[static_cast<std::size_t>(ends.first)].push_back(ends.second);
      sharp_ends[static_cast<std::size_t>(ends.second)].push_back(ends.first);
    }
  }
  // A crease vertex whose crease turns by more than the angle: a corner.
  for (std::size_t v = 0; v < points.size(); ++v) {
    if (sharp_ends[v].size() != 2) continue;
    const Vec3 in = points[v] - points[static_cast<std::size_t>(sharp_ends[v][0])];
    const Vec3 out_dir = points[static_cast<std::size_t>(sharp_ends[v][1])] - points[v];
    const double lengths = norm(in) * norm(out_dir);
    if (lengths > 0.0 && dot(in, out_dir) < cos_limit * lengths)
      out.vertices.push_back({static_cast<std::int32_t>(v), kInfiniteSharpness});
  }
  return out;
}

SharpFeatures merged(const SharpFeatures& tags, const SharpFeatures& detected) {
  // The tags last: RgbMesh::from_triangles lets the last entry for an edge or vertex count.
  SharpFeatures out = detected;
  out.method = tags.method;
  out.edges.insert(out.edges.end(), tags.edges.begin(), tags.edges.end());
  out.vertices.insert(out.vertices.end(), tags.vertices.begin(), tags.vertices.end());
  return out;
}

}  // namespace rgbmesh
