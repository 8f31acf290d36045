#pragma once
/// \file
/// Input meshes before they become RGB meshes: a polygon soup as read from a file, and the
/// checks and repairs that turn it into a clean, consistently oriented, manifold triangle mesh.
///
/// Every problem is reported as an InputError whose message is one line naming the offending
/// element (face or vertex index, 0-based, in the file's own numbering); the caller prefixes the
/// file name. Repairs that do not need guessing (re-orienting an orientable surface, dropping
/// unreferenced vertices, fan-splitting polygons when asked) are applied and described in
/// `notes`, one line each, so that the user is told.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbmesh/errors.hpp"  // InputError
#include "rgbmesh/vec3.hpp"

namespace rgbmesh {


struct PolygonSoup {
  std::vector<Vec3> points;
  /// Faces as vertex index lists; indices are 64-bit and unchecked so that readers can pass
  /// through whatever the file says and the checks below name the bad face.
  std::vector<std::vector<std::int64_t>> faces;
};

struct SoupOptions {
  /// Split polygons with more than three vertices into triangle fans (otherwise: an error).
  bool triangulate = false;
};

struct TriangleMeshData {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::string> notes;  ///< repairs applied, one human-readable line each
};

/// Checks, in this order, and throws InputError on the first failure:
/// empty mesh; NaN/inf coordinates; faces with fewer than 3 vertices; index out of range;
/// non-triangle faces (unless options.triangulate); degenerate triangles (a repeated vertex or
/// zero area); duplicate triangles (same vertex set); non-manifold edges (more than two
/// triangles) and vertices (star not a single fan); non-orientable surfaces.
/// Repairs: unreferenced vertices are dropped; an orientable surface with inconsistently
/// oriented triangles is re-oriented (each connected component keeps the orientation of its
/// lowest-numbered triangle).
TriangleMeshData prepare_triangle_mesh(const PolygonSoup& soup, const SoupOptions& options = {});

}  // namespace rgbmesh
