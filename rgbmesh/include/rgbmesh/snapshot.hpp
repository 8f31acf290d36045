#pragma once
// A compact, array-based copy of the current mesh for output: what writers and external
// solvers consume. Vertices and triangles are renumbered 0..n-1 (dead slots skipped).

#include <array>
#include <cstdint>
#include <optional>
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
  // A point-data array equal to the points themselves (components 3, values empty): writers
  // write the points' memory under this name, so that it is not held twice.
  bool same_as_points = false;
};

// The complete RGB state of a mesh as plain arrays (what rgb_state.hpp saves and restores;
// see there for why these arrays determine the mesh). VTK XML files carry it.
struct RgbState {
  // Bumped when the meaning of the arrays changes; readers refuse versions they do not know.
  static constexpr int kVersion = 1;
  int version = kVersion;
  // The base mesh Σ0: control points (exact) and counter-clockwise triangles, as
  // RgbMesh::from_triangles takes them.
  std::vector<Vec3> base_points;
  std::vector<std::array<std::int32_t, 3>> base_triangles;
  // One entry per point of the snapshot (file) the state belongs to.
  // base_vertex[i]: the base index of point i, or -1 for an inserted vertex.
  std::vector<std::int32_t> base_vertex;
  // parents[i]: the points (indices into the same point list) whose edge point i split, or
  // {-1, -1} for a base vertex.
  std::vector<std::array<std::int32_t, 2>> parents;
};

struct MeshSnapshot {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise
  std::vector<std::uint8_t> vertex_level;             // insertion level per point
  std::vector<std::uint8_t> triangle_level;
  std::vector<Color> triangle_color;
  std::vector<VertexHandle> vertex_handle;      // point i -> mesh vertex (RgbMesh::snapshot)
  std::vector<TriangleHandle> triangle_handle;  // cell i -> mesh triangle (RgbMesh::snapshot)
  std::vector<NamedArray> point_data;           // extra per-point arrays
  std::vector<NamedArray> cell_data;            // extra per-cell arrays
  // The RGB state, for formats that carry it (VTK XML); indices are point indices.
  std::optional<RgbState> state;
};

}  // namespace rgbmesh
