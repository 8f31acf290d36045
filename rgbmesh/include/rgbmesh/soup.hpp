#pragma once
/// \file
/// Input meshes before they become RGB meshes: a polygon soup as read from a file, and the
/// checks and repairs that turn it into a clean, consistently oriented, manifold triangle mesh.
///
/// Every problem is reported as an InputError whose message is one line naming the offending
/// element (face or vertex index, 0-based, in the file's own numbering; vertices by position where
/// the file does not number them); the caller prefixes the file name. Defects of the mesh itself
/// that a repair would fix are MeshDefectErrors (errors.hpp). Repairs that do not need guessing
/// (re-orienting an orientable surface, dropping unreferenced vertices, splitting polygons
/// when asked) are applied and described in `notes`, one line each, so that the user is told;
/// the others only when the caller supplies a repair (SoupOptions::repair, rgbmesh::repair), so
/// that rgbmesh::core needs nothing but the standard library.

#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbmesh/errors.hpp"  // InputError
#include "rgbmesh/sharpness.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh {


struct PolygonSoup {
  std::vector<Vec3> points;
  /// Faces as vertex index lists; indices are 64-bit and unchecked so that readers can pass
  /// through whatever the file says and the checks below name the bad face.
  std::vector<std::vector<std::int64_t>> faces;
  /// Whether the vertex numbers are the file's own. False for STL, whose vertices are the facets'
  /// corners merged by position: messages then name vertices by their positions.
  bool numbered_vertices = true;
  /// Sharp features as the file tags them (OpenSubdiv's OBJ tags 't crease', 't corner',
  /// 't creasemethod'): vertices by their index in `points`, counted from 0 as the tags count.
  SharpFeatures sharp{};
  /// The file asks for boundary vertices of a single face to be corners (OpenSubdiv's
  /// 't interpolateboundary 1/0/0 1', "edge and corner").
  bool boundary_corners = false;
  /// What the reader ignored or read in a way the user should know, one line each.
  std::vector<std::string> notes{};
};

/// A repair of a triangle soup: receives the points (all finite) and the triangles (indices in
/// range; polygons already split), may change both in any way (merge, remove, add points;
/// remove, reorder, re-orient triangles), and appends to `notes` one line per kind of change, with
/// counts. Throws InputError when nothing usable is left. rgbmesh::repair::soup_repair() gives
/// one (rgbmesh/repair/repair.hpp).
using SoupRepair = std::function<void(std::vector<Vec3>& points,
                                      std::vector<std::array<std::int32_t, 3>>& triangles,
                                      std::vector<std::string>& notes)>;

struct SoupOptions {
  /// Split polygons with more than three vertices into triangle fans (otherwise: an error).
  bool triangulate = false;
  /// When set, applied to the triangles before the checks; what it gives must then pass them (an
  /// InputError "could not be repaired: ..." otherwise). Polygons still need `triangulate`.
  SoupRepair repair;
  /// Above 0 (and below 180): edges whose triangles' normals differ by more than this many
  /// degrees become infinitely sharp, and so on (detect_sharp_features, sharpness.hpp), added
  /// to the file's own tags, with a note that counts them. 0: only the file's tags.
  double sharp_angle = 0.0;
};

struct TriangleMeshData {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::string> notes;  ///< repairs applied, one human-readable line each
  /// The soup's sharp features in the numbering of `points` (RgbMesh::from_triangles takes them).
  SharpFeatures sharp{};
};

/// Checks, in this order, and throws InputError on the first failure:
/// empty mesh; NaN/inf coordinates; faces with fewer than 3 vertices; index out of range;
/// non-triangle faces (unless options.triangulate); then, after options.repair when it is set,
/// the defects (MeshDefectError): degenerate triangles (a repeated vertex or zero area); duplicate
/// triangles (same vertex set); non-manifold edges (more than two triangles) and vertices (star
/// not a single fan); non-orientable surfaces.
/// Sharp features: a tag naming a vertex the soup does not have, or an edge none of its faces
/// has, is an InputError ("crease tag 3 (4, 9) is not an edge of the mesh"); tags follow the
/// vertices through the repairs (by position after options.repair; a note counts any that no
/// longer name an edge).
/// Repairs: unreferenced vertices are dropped; an orientable surface with inconsistently
/// oriented triangles is re-oriented (each connected component keeps the orientation of its
/// lowest-numbered triangle). Without options.repair, a note says when the vertices sit at fewer
/// distinct positions than there are vertices (faces that meet only at equal positions are not
/// joined: the mesh falls apart into more pieces than the user sees).
TriangleMeshData prepare_triangle_mesh(const PolygonSoup& soup, const SoupOptions& options = {});

}  // namespace rgbmesh
