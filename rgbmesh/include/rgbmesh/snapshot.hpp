#pragma once
// A compact, array-based copy of the current mesh for output: what writers and external
// solvers consume. Vertices and triangles are renumbered 0..n-1 (dead slots skipped).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rgbmesh/handles.hpp"
#include "rgbmesh/sharpness.hpp"
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
  // 1: the arrays below but `sharp`; 2 adds `sharp`. A state without sharp features is written
  // as version 1, which earlier builds read too (version_for).
  static constexpr int kVersion = 2;
  static int version_for(const SharpFeatures& sharp) { return sharp.empty() ? 1 : 2; }
  int version = kVersion;
  // The base mesh Σ0: control points (exact) and counter-clockwise triangles, as
  // RgbMesh::from_triangles takes them.
  std::vector<Vec3> base_points;
  std::vector<std::array<std::int32_t, 3>> base_triangles;
  // The base mesh's creases and corners (RgbMesh::sharp_features; version 2).
  SharpFeatures sharp;
  // One entry per point of the snapshot (file) the state belongs to.
  // base_vertex[i]: the base index of point i, or -1 for an inserted vertex.
  std::vector<std::int32_t> base_vertex;
  // parents[i]: the points (indices into the same point list) whose edge point i split, or
  // {-1, -1} for a base vertex.
  std::vector<std::array<std::int32_t, 2>> parents;
};

// One process's piece of a data set split among processes: the cells whose part is `which`,
// renumbered over the points they use (in the order they first use them), with the rows of
// the kept cells and points in the whole data set.
template <std::size_t N>
struct CellPiece {
  std::vector<std::array<std::int32_t, N>> cells;
  std::vector<std::size_t> cell_rows, point_rows;
};
template <std::size_t N>
CellPiece<N> cell_piece(const std::vector<std::array<std::int32_t, N>>& cells, std::size_t points,
                        const std::vector<std::int32_t>& part, std::int32_t which) {
  CellPiece<N> piece;
  std::vector<std::int32_t> point_of(points, -1);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (part[c] != which) continue;
    piece.cell_rows.push_back(c);
    std::array<std::int32_t, N> renumbered{};
    for (std::size_t k = 0; k < N; ++k) {
      const auto p = static_cast<std::size_t>(cells[c][k]);
      if (point_of[p] < 0) {
        point_of[p] = static_cast<std::int32_t>(piece.point_rows.size());
        piece.point_rows.push_back(p);
      }
      renumbered[k] = point_of[p];
    }
    piece.cells.push_back(renumbered);
  }
  return piece;
}

// The given rows of each array (a same_as_points array stays one, without values).
inline std::vector<NamedArray> array_rows(const std::vector<NamedArray>& arrays, const std::vector<std::size_t>& rows) {
  std::vector<NamedArray> out;
  for (const NamedArray& a : arrays) {
    NamedArray b{a.name, a.components, {}, a.same_as_points};
    if (!a.same_as_points) {
      const auto k = static_cast<std::size_t>(a.components);
      for (const std::size_t r : rows)
        b.values.insert(b.values.end(), a.values.begin() + static_cast<std::ptrdiff_t>(r * k),
                        a.values.begin() + static_cast<std::ptrdiff_t>((r + 1) * k));
    }
    out.push_back(std::move(b));
  }
  return out;
}

struct MeshSnapshot {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise
  std::vector<std::uint8_t> vertex_level;             // insertion level per point
  std::vector<std::uint8_t> triangle_level;
  std::vector<Color> triangle_color;
  std::vector<VertexHandle> vertex_handle;      // point i -> mesh vertex (RgbMesh::snapshot)
  std::vector<TriangleHandle> triangle_handle;  // cell i -> mesh triangle (RgbMesh::snapshot)
  // With sharp features only (else empty): each point's subdivision rule at its shown level
  // (0 smooth, 1 dart, 2 crease, 3 corner; VertexRule), written as point data "vertex_rule".
  std::vector<std::uint8_t> vertex_rule;
  // The sharp features as the current mesh has them (RgbMesh::snapshot): the sharp interior
  // edges between points with their sharpness at the edges' levels, the sharp base vertices with
  // theirs at their shown levels, point indices. OBJ files carry them as OpenSubdiv's tags, so
  // that the file read back as a base mesh keeps its creases (exactly for uniform meshes).
  SharpFeatures sharp;
  std::vector<NamedArray> point_data;           // extra per-point arrays
  std::vector<NamedArray> cell_data;            // extra per-cell arrays
  // The RGB state, for formats that carry it (VTK XML); indices are point indices.
  std::optional<RgbState> state;
  // A piece's state (save_piece_state: the points' entries first, then their ancestors), for
  // the pieces of a distributed run, which read_rgb_pieces joins. VTK XML: field data.
  std::optional<RgbState> piece_state;
};

}  // namespace rgbmesh
