#pragma once
/// \file
/// Repairing meshes as tools export them, so that they pass the checks every input goes through
/// (prepare_triangle_mesh, soup.hpp): positions that several vertices share are merged,
/// degenerate and needle triangles collapsed (not deleted, so that no hole opens), duplicate
/// triangles removed, non-manifold edges and vertices split, the surface oriented consistently
/// (cut open where it cannot be), isolated vertices dropped. The geometric work is done by CGAL's
/// Polygon Mesh Processing (CGAL 5.5: remove_isolated_points_in_polygon_soup,
/// polygon_soup_to_polygon_mesh, remove_degenerate_faces,
/// experimental::remove_almost_degenerate_faces); CGAL stays private to this module. The steps
/// on the whole soup are linear-time array passes that follow CGAL's rules (orient_triangles.hpp
/// follows orient_polygon_soup, tested against it), so that a repair costs about as much as a
/// second reading of the file (bench/bench_repair.cpp); the halfedge mesh is built only when a
/// triangle is degenerate, a needle or a cap.
///
/// The geometry moves by at most RepairOptions::max_move times the bounding-box diagonal: only
/// edges that short are collapsed, and only caps that flat flipped. Everything else is a change of
/// connectivity at unchanged positions.
///
/// The reading path takes the repair as a function object (SoupOptions::repair), so that the
/// tool, the Python package and rgbmesh::fit's make_base get it the same way:
/// \code
///   rgbmesh::SoupOptions options;
///   options.repair = rgbmesh::repair::soup_repair();
///   rgbmesh::TriangleMeshData mesh = rgbmesh::read_mesh("part.stl", options);  // notes: what changed
/// \endcode

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::repair {

/// The thresholds of the geometric repairs (docs/command-line.md says why these values).
struct RepairOptions {
  /// Bound on how far any point of the surface moves, relative to the bounding-box diagonal:
  /// needles are collapsed only along edges at most this long, caps flipped only when their apex
  /// is at most this far from their longest edge. 1e-6 is about ten times the rounding of the
  /// single-precision coordinates that STL stores (2^-24 relative): shorter is an artefact of
  /// the export, not a feature of the shape.
  double max_move = 1e-6;
  /// A triangle is a needle when its longest edge is at least this many times its shortest.
  double needle_ratio = 1000;
  /// A triangle is a cap when its largest angle is at least this many degrees.
  double cap_angle_degrees = 179.9;
};

/// What a repair did, by kind; counts are of the input's elements unless said otherwise.
struct RepairReport {
  std::size_t snapped_coordinates = 0;  ///< coordinates within 1e-12 of the diagonal of zero, set to zero
  std::size_t isolated_vertices = 0;    ///< vertices no triangle used, dropped
  std::size_t merged_vertices = 0;      ///< vertices merged into another at the same position
  std::size_t zero_area_triangles = 0;  ///< collapsed: coincident or collinear corners
  std::size_t repeated_triangles =
      0;  ///< copies of a triangle with the same corners and orientation, removed
  std::size_t back_to_back_removed = 0;  ///< pairs of opposite copies between parts that touch, both removed
  std::size_t back_to_back_kept = 0;     ///< pairs of opposite copies on a two-sided sheet, one copy kept
  std::size_t non_manifold_edges = 0;    ///< edges of more than two triangles, split
  std::size_t cut_edges = 0;             ///< edges cut open so that the surface could be oriented
  std::size_t split_vertices = 0;        ///< non-manifold vertices split into several
  std::size_t vertex_copies = 0;         ///< the vertices they became
  std::size_t reoriented_triangles = 0;  ///< triangles whose orientation was reversed
  std::size_t needle_triangles = 0;      ///< triangles removed by collapsing the short edges of needles
  std::size_t flipped_caps = 0;          ///< caps whose longest edge was flipped
  std::size_t removed_caps = 0;          ///< caps on the boundary, removed
  double max_move = 0;                   ///< the bound used, in the mesh's units

  bool changed() const;
  /// "repaired: merged 952 duplicate vertices, collapsed 1 zero-area triangle, split 1 non-manifold
  /// vertex into 2", or "repaired: nothing needed repair".
  std::string note() const;
};

/// Repairs a triangle soup in place. The points must be finite and the indices in range (as
/// prepare_triangle_mesh has them before its checks). The result is meant to pass those checks;
/// the caller checks it (a repair cannot always succeed: a surface whose triangles cross each
/// other stays so, a cap whose edge cannot be flipped stays).
RepairReport repair_triangles(std::vector<Vec3>& points, std::vector<std::array<std::int32_t, 3>>& triangles,
                              const RepairOptions& options = {});

/// repair_triangles as SoupOptions::repair wants it (its note in `notes`).
SoupRepair soup_repair(const RepairOptions& options = {});

/// SoupOptions with `triangulate` and, when `repair`, soup_repair(): what the tool's
/// --triangulate and --repair ask for.
SoupOptions soup_options(bool triangulate, bool repair);

/// `soup` through prepare_triangle_mesh with soup_repair() (and polygons split when `triangulate`),
/// given back as a soup of the valid triangle mesh that came out, its notes appended to `notes`:
/// for code that takes soups (rgbmesh::fit's make_base). When no valid mesh comes out, `soup` is
/// given back unchanged, with a note saying why.
PolygonSoup repaired_soup(const PolygonSoup& soup, bool triangulate, std::vector<std::string>& notes);

}  // namespace rgbmesh::repair
