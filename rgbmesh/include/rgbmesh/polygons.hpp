#pragma once
/// \file
/// Polygon faces split into triangles that cover the polygon once: convex, concave and warped
/// polygons, refusing what is not a disk (a polygon that crosses itself or has no area).

#include <array>
#include <cstdint>
#include <vector>

#include "rgbmesh/errors.hpp"  // InputError
#include "rgbmesh/vec3.hpp"

namespace rgbmesh {

/// How triangulate_polygon split a polygon.
enum class PolygonSplit : std::uint8_t {
  fan,          ///< planar and convex: a fan from its first corner
  ears,         ///< concave (or convex with corners in line): ears cut in its plane, best-shaped first
  warped_ears,  ///< not planar: ears cut in its best-fit plane, best-shaped (in space) first
};

struct PolygonTriangles {
  /// n - 2 triangles, as positions in the polygon's corner list (0 .. n-1), each turning as the
  /// polygon does.
  std::vector<std::array<std::int32_t, 3>> triangles;
  PolygonSplit split = PolygonSplit::fan;
  /// The largest distance of a corner from the polygon's best-fit plane, relative to the
  /// polygon's size (the diagonal of its bounding box).
  double out_of_plane = 0;
};

/// Polygons whose corners stray further than this (relative to their size) from their best-fit
/// plane are warped: no split of them is the surface, and the caller should say so.
inline constexpr double kWarpedPolygon = 1e-4;

/// Splits the polygon with these corners (in order, at least 3) into triangles without overlaps.
/// The plane is the polygon's own (Newell's normal, which is its area vector). A planar convex
/// polygon is split as a fan from corner 0 (the split of most tools); any other polygon by ear
/// cutting in the plane, best-shaped triangle first, so that a concave polygon is covered once
/// and a warped one by well-shaped triangles. Throws InputError (the caller names the face) when
/// the polygon has no area, crosses itself in its plane (a pentagram, a bowtie, a polygon that
/// winds twice) or has corners in line where no triangle can be cut. Time about n log n for a
/// polygon of n corners whose reflex corners are spread out.
PolygonTriangles triangulate_polygon(const std::vector<Vec3>& corners);

}  // namespace rgbmesh
