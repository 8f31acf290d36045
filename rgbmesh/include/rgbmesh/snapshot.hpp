#pragma once
// A compact, array-based copy of the current mesh for output: what writers and external
// solvers consume. Vertices and triangles are renumbered 0..n-1 (dead slots skipped).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/handles.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh {

enum class Color : std::uint8_t { green = 0, red = 1, blue = 2 };

struct NamedArray {
  std::string name;
  int components = 1;
  std::vector<double> values;  // size = components * number of points (or cells)
};

struct MeshSnapshot {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise
  std::vector<std::uint8_t> vertex_level;             // insertion level per point
  std::vector<std::uint8_t> triangle_level;
  std::vector<Color> triangle_color;
  std::vector<VertexHandle> vertex_handle;      // point i -> mesh vertex
  std::vector<TriangleHandle> triangle_handle;  // cell i -> mesh triangle
  std::vector<NamedArray> point_data;           // extra per-point arrays
  std::vector<NamedArray> cell_data;            // extra per-cell arrays
};

}  // namespace rgbmesh
