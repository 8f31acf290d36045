#pragma once
// Sharp features inside the core: the sharp base edges ("rails") with the sharpness of every
// piece of them at every level, and the evolution of one vertex's control point through the
// levels where its rules change (semi-sharp features decaying) or never settle into a closed
// form (darts). The rules themselves are loop_rules.hpp's.
//
// Why rails: a sharp edge of level l is always a piece of a sharp base edge (Loop's interior
// edges are smooth), so its sharpness is a function of (base edge, level, position along it).
// A vertex inserted on a sharp base edge keeps that base edge and its dyadic position there;
// everything else about sharpness follows, for any vertex set and any order of operations.
// Edges along base edges are never swapped (only red edges and the green diagonals made by
// BB-swaps inside a parent triangle are), so nothing else needs to be stored per edge.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/sharpness.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::detail {

/// A sharp interior base edge: its ends (a < b) and sharpness (0 < s, at most 10).
struct Rail {
  std::int32_t a = -1, b = -1;
  float sharpness = 0.0f;
};

/// The sharp features of a base mesh, fixed once built: shared by copies of the mesh.
class CreaseTable {
 public:
  /// `features` in normal form (RgbMesh::sharp_features: interior edges only, a < b, sorted,
  /// no zero entries, values at most 10).
  CreaseTable(const SharpFeatures& features, std::size_t base_vertices);

  /// The features in normal form (RgbMesh::sharp_features).
  const SharpFeatures& features() const { return features_; }
  CreaseMethod method() const { return method_; }
  const std::vector<Rail>& rails() const { return rails_; }
  /// The rail of base edge (a, b), either order, or -1.
  std::int32_t rail_of(std::int32_t a, std::int32_t b) const;
  /// The rails that end at base vertex v.
  const std::vector<std::int32_t>& rails_at(std::int32_t v) const;
  /// The sharpness of piece `index` (counted from rail.a, 0 .. 2^level - 1) of rail r at `level`.
  float segment(std::int32_t r, int level, std::uint64_t index) const;
  /// The sharpness of base vertex v at `level`.
  float vertex(std::int32_t v, int level) const;
  bool has_vertex_sharpness() const { return !vertex_sharpness_.empty(); }

 private:
  void build_chaikin();

  SharpFeatures features_;
  CreaseMethod method_ = CreaseMethod::uniform;
  std::vector<Rail> rails_;
  std::unordered_map<std::uint64_t, std::int32_t> by_ends_;
  std::vector<std::vector<std::int32_t>> rails_at_;  // per base vertex
  std::vector<float> vertex_sharpness_;              // per base vertex; empty if none is sharp
  // Chaikin: per rail, the pieces' sharpness level by level, until all are 0 (semi-sharp rails
  // only; at most 11 levels, since every value drops by at least 1 per level).
  std::vector<std::vector<std::vector<float>>> chaikin_;
};

/// An edge at a vertex (a "spoke") as the evolution needs it: where its far end is at the
/// vertex's level, and which piece of which rail it is.
struct Spoke {
  Vec3 point;
  bool boundary = false;     ///< a boundary edge: infinitely sharp
  std::int32_t rail = -1;    ///< the sharp base edge it lies on, or -1 (smooth)
  std::uint64_t piece = 0;   ///< its index along the rail at the vertex's level
  bool vertex_first = true;  ///< the vertex is the piece's end nearer rail.a
};

/// A vertex and its Loop 1-ring at its level: counter-clockwise; for a boundary vertex the
/// first and last spokes are its boundary edges.
struct Ring {
  Vec3 centre;
  int level = 0;
  std::int32_t base_vertex = -1;  ///< its base index (for its own sharpness), or -1
  bool open = false;
  std::vector<Spoke> spokes;
};

/// A vertex's control points level by level from its level on, for as long as its rules vary
/// (semi-sharp features) or for good (a dart), then the closed form of its final rule:
/// p^{l+m+k} = g^k points[m] + (1 - g^k) limit.
struct Evolution {
  std::vector<Vec3> points;
  VertexRule rule = VertexRule::smooth;
  double g = 0.25;
  Vec3 limit;
};

/// The rule of the vertex of `ring` at `level` (>= ring.level).
VertexRule ring_rule(const CreaseTable* table, const Ring& ring, int level);

/// Whether the rules around the vertex are the same at every level from ring.level on and
/// have a closed form (smooth, crease, corner): then evolve gives one point.
bool settled(const CreaseTable* table, const Ring& ring);

/// Subdivides the ring level by level with the rules of loop_rules.hpp until they settle;
/// darts are followed to kMaxLevel (`last_level`) and their limit found by subdividing on
/// until the ring stops moving (OpenSubdiv's Limit() uses the smooth mask at darts, which is
/// not the limit its own refinement converges to; docs/concepts.md).
Evolution evolve(const CreaseTable* table, const Ring& ring, int last_level);

}  // namespace rgbmesh::detail
