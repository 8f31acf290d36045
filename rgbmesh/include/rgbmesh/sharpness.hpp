#pragma once
/// \file
/// Sharp features of a base mesh: creases (edges with a sharpness) and corners (vertices with a
/// sharpness), as OpenSubdiv and RenderMan define them for Loop subdivision.
///
/// Sharpness is a number per base edge and per base vertex: 0 is smooth, 10 and above is
/// infinitely sharp (the edge stays a crease curve at every level, the vertex never moves),
/// and a value s in between is semi-sharp: the feature is sharp for about s levels of
/// subdivision and then smooth, which rounds it with a radius that shrinks as s grows.
/// Boundary edges are always infinitely sharp (their tags are ignored). The subdivision rules
/// that follow from the tags (vertex classes, masks, decay of semi-sharp values, limits) are
/// in loop_rules.hpp; RgbMesh applies them through every operation.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/vec3.hpp"

namespace rgbmesh {

/// Sharpness at and above which a feature is infinitely sharp (OpenSubdiv's
/// Sdc::Crease::SHARPNESS_INFINITE).
inline constexpr float kInfiniteSharpness = 10.0f;

/// How a semi-sharp edge's children get their sharpness (OpenSubdiv's Sdc::Options::
/// CreasingMethod): uniform subtracts 1 per level; Chaikin first averages each end with the
/// neighbouring semi-sharp edges there (3/4 its own, 1/4 theirs), which makes a crease whose
/// sharpness varies along its length round off gradually.
enum class CreaseMethod : std::uint8_t { uniform, chaikin };

/// "uniform" or "chaikin".
const char* to_string(CreaseMethod method);

/// The subdivision rule of a vertex at one level (OpenSubdiv's Sdc::Crease::Rule): smooth (no
/// sharp edge), dart (one), crease (two), corner (three or more, or a sharp vertex). Boundary
/// edges count as sharp.
enum class VertexRule : std::uint8_t { smooth, dart, crease, corner };

/// "smooth", "dart", "crease", "corner".
const char* to_string(VertexRule rule);

/// An edge of the base mesh, by its two base vertices (either order), and its sharpness.
struct SharpEdge {
  std::int32_t a = -1, b = -1;
  float sharpness = kInfiniteSharpness;
};

/// A base vertex and its sharpness (a corner when infinite).
struct SharpVertex {
  std::int32_t v = -1;
  float sharpness = kInfiniteSharpness;
};

/// The sharp features of a base mesh. Entries with sharpness 0 are allowed (they say
/// "smooth"); when an edge or vertex is listed several times, the last entry counts, as in
/// OpenSubdiv's shape files. RgbMesh::from_triangles checks them (an InputError names the
/// entry that is not an edge or vertex of the mesh, or whose sharpness is negative or not a
/// number) and keeps them in a normal form (RgbMesh::sharp_features).
struct SharpFeatures {
  std::vector<SharpEdge> edges;
  std::vector<SharpVertex> vertices;
  CreaseMethod method = CreaseMethod::uniform;
  /// No sharp edge and no sharp vertex (the method alone changes nothing).
  bool empty() const;
  bool operator==(const SharpFeatures& o) const;
  bool operator!=(const SharpFeatures& o) const { return !(*this == o); }
};

/// Sharp features found from the geometry, the convention of VTK's feature edges, CGAL's
/// detect_sharp_edges and Blender's auto smooth: an interior edge whose two triangles' normals
/// differ by more than `angle_degrees` is infinitely sharp. A vertex where such a crease turns
/// by more than `angle_degrees` (the angle between the directions in and out of the vertex
/// along its two sharp edges, the boundary counting as sharp) becomes an infinitely sharp
/// corner; vertices with three or more sharp edges are corners by Loop's rules anyway, and a
/// sharp edge that ends inside smooth surface gives a dart. `angle_degrees` in (0, 180);
/// the triangles must be a valid mesh (prepare_triangle_mesh's).
SharpFeatures detect_sharp_features(const std::vector<Vec3>& points,
                                    const std::vector<std::array<std::int32_t, 3>>& triangles, double angle_degrees);

/// `tags` with `detected` added where the tags say nothing: an edge or vertex the tags name
/// keeps the tags' sharpness (they may make it semi-sharp or smooth on purpose); the method is
/// the tags'.
SharpFeatures merged(const SharpFeatures& tags, const SharpFeatures& detected);

}  // namespace rgbmesh
