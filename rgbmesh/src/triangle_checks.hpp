#pragma once
// The checks that both entry points make on a triangle mesh before it becomes an RGB mesh:
// prepare_triangle_mesh (the file path, soup.cpp) and RgbMesh::from_triangles (the library,
// mesh_construction.cpp). One copy, so that both reject the same inputs with the same
// messages: one line naming the offending element, thrown as InputError.
//
// Everything is O(n log n): the combinatorial checks sort half-edges and triangle keys instead
// of building per-vertex adjacency lists, and vertex-manifoldness is a union-find over corners.
// Internal to rgbmesh::core (not installed).

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::detail {

using Triangle = std::array<std::int32_t, 3>;

// The RGB mesh numbers vertices and triangles with int32, and corners (3 per triangle) index
// the union-find, so the triangle count is bounded by a third of the int32 range.
constexpr std::int64_t max_vertices = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t max_triangles = std::numeric_limits<std::int32_t>::max() / 3;

std::string plural(std::size_t n, const char* singular, const char* plural_form);

// How messages name the input's faces and where they come from: a file's "face 3 ... the file
// has 6 vertices", or the library's "triangle 3 ... the mesh has 6 vertices".
struct Wording {
  const char* face;   // "face" or "triangle"
  const char* faces;  // its plural
  const char* whole;  // "the file" or "the mesh"
};
inline constexpr Wording file_wording{"face", "faces", "the file"};
inline constexpr Wording mesh_wording{"triangle", "triangles", "the mesh"};

// Names the elements of the input in messages. Triangles: without triangulation triangle i is
// face i of the input; after splitting polygons, the source face is given too so that the user can
// find it in the file. Vertices: by their number where the input numbers them; by their position
// where it does not (STL, whose vertices are the facets' corners merged by position, and a
// repaired mesh, whose vertices are no longer the file's).
class TriangleNames {
 public:
  // source_face: empty when triangle i is face i; must outlive this object.
  explicit TriangleNames(const std::vector<std::int64_t>& source_face) : source_face_(source_face) {}
  // Vertices named by their positions in `points` (which must outlive this object).
  TriangleNames(const std::vector<std::int64_t>& source_face, const std::vector<Vec3>& points)
      : source_face_(source_face), points_(&points) {}
  std::string one(std::int32_t t) const;                               // "4" or "4 (from face 2)"
  std::string list(const std::vector<std::int32_t>& triangles) const;  // "2, 5, 8 (from faces 1, 4, 6)"
  bool by_position() const { return points_ != nullptr; }
  std::string vertex(std::int32_t v) const;                // "vertex 5", "the vertex at (1.5, 2, -3)"
  std::string edge(std::int32_t a, std::int32_t b) const;  // "edge (0, 1)", "the edge from (...) to (...)"
  std::string position(std::int32_t v) const;              // "(1.5, 2, -3)"

 private:
  const std::vector<std::int64_t>& source_face_;
  const std::vector<Vec3>* points_ = nullptr;
};

// "(1.5, 2, -3)": the shortest text that reads back as the same doubles.
std::string point_text(const Vec3& p);

// Empty mesh (no points or no faces), too many points, non-finite coordinates (of every
// point, referenced or not: such a value means the input is broken).
void check_points(const std::vector<Vec3>& points, std::size_t n_faces, const Wording& wording);

// Every index of every face in [0, n_points). Faces: any range of ranges of integers.
template <class Faces>
void check_indices(const Faces& faces, std::size_t n_points, const Wording& wording) {
  const auto n = static_cast<std::int64_t>(n_points);
  std::size_t f = 0;
  for (const auto& face : faces) {
    for (const auto index : face) {
      const auto v = static_cast<std::int64_t>(index);
      if (v < 0 || v >= n)
        throw InputError(std::string(wording.face) + " " + std::to_string(f) + " references vertex " +
                         std::to_string(v) + " but " + wording.whole + " has " +
                         plural(n_points, "vertex", "vertices"));
    }
    ++f;
  }
}

// At most max_triangles triangles.
void check_triangle_count(std::uint64_t n_triangles);

// One side of a triangle: half-edge k of triangle t runs from corner k to corner k+1.
struct HalfEdge {
  std::int32_t lo, hi;  // endpoints, lo < hi
  std::int32_t triangle;
  std::int8_t k;
  bool forward;  // runs lo -> hi

  friend bool operator<(const HalfEdge& a, const HalfEdge& b) {
    if (a.lo != b.lo) return a.lo < b.lo;
    if (a.hi != b.hi) return a.hi < b.hi;
    return a.triangle < b.triangle;
  }
  bool same_edge(const HalfEdge& o) const { return lo == o.lo && hi == o.hi; }
};

// What the points must be besides finite.
enum class AreaCheck : bool { skip, zero_area_is_degenerate };

// The checks of a triangle list whose indices are in range, in this order, throwing
// MeshDefectError (with what a repair does about it) on the first failure: degenerate triangles (a repeated
// vertex; with zero_area_is_degenerate also zero area, i.e. collinear or coincident corners); duplicate
// triangles (same vertex set, whatever the order: this covers two triangles glued back to back, a "pillow");
// edges of more than two triangles; vertices whose triangles form several fans; non-orientable surfaces.
// Returns the half-edges sorted so that the sides of one edge are adjacent, and in `flip` which triangles to
// reverse for a consistent orientation (each edge-connected component keeps the orientation of its
// lowest-numbered triangle).
struct SurfaceCheck {
  std::vector<HalfEdge> half_edges;
  std::vector<bool> flip;
  std::size_t flips = 0;
};
SurfaceCheck check_surface(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                           const TriangleNames& name, AreaCheck area);

// Two neighbouring triangles that run their shared edge (lo, hi) in the same direction: of
// all such pairs, the one whose later triangle comes first (as the other checks name the
// duplicate or third triangle that comes first). found is false when the orientation is
// consistent.
struct InconsistentPair {
  bool found = false;
  std::int32_t first = -1, second = -1;  // triangle indices, first < second
  std::int32_t lo = -1, hi = -1;         // the shared edge
};
InconsistentPair first_inconsistent_pair(const std::vector<HalfEdge>& half_edges);

}  // namespace rgbmesh::detail
