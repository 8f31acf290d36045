#pragma once
// The two reconstruction methods behind reconstruct_surface (reconstruct.hpp), private to
// rgbmesh::fit: each returns its triangles as a soup, or throws MethodFailed saying why it
// could not, so that the caller can try the other or refuse.

#include <stdexcept>
#include <string>
#include <vector>

#include "rgbmesh/fit/reconstruct.hpp"

namespace rgbmesh::fit::detail {

class MethodFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Points with oriented, unit normals.
struct OrientedCloud {
  std::vector<Vec3> points, normals;
};

// The zero level set of CGAL's Poisson implicit function for the cloud, meshed as a closed
// manifold (soup of triangles), with at most options.max_vertices_per_face * options.faces
// vertices. `spacing` is the cloud's average spacing, `diagonal` its bounding box's.
PolygonSoup poisson_surface(const OrientedCloud& cloud, double spacing, double diagonal,
                            const ReconstructionOptions& options, const StageControl& control,
                            const std::string& stage);

// CGAL's advancing-front triangles through the points (indices into `points`). Candidate
// triangles whose Delaunay sphere is larger than a few local spacings of their corners are
// refused, so that the surface does not bridge gaps of the scan.
PolygonSoup advancing_front_surface(const std::vector<Vec3>& points, const std::vector<double>& spacing,
                                    const StageControl& control, const std::string& stage);

// Fills the holes of a valid triangle mesh whose boundary is shorter than `length` (a fair
// triangulation of the hole, refined to its surroundings). Returns how many were filled.
std::size_t fill_small_holes(TriangleMeshData& mesh, double length);

// Where a surface's triangles at a vertex form several fans (parts that meet only at that
// point), all but the largest fan get a copy of the vertex of their own: the soup is then a
// manifold at its vertices, and each part is kept.
void split_pinched_vertices(PolygonSoup& soup);

// An open scan's surface trimmed to the points (reconstruct.cpp): the triangles with an edge
// midpoint or centroid farther from the nearest point than `spacings` times that point's local
// spacing go (a bridging triangle or a cap over a part the scan did not see); a vertex where
// the parts left met only at a point is split, one copy per fan; then the components under 0.5%
// of the triangles go (islands over gaps). With `border_only`, only the triangles along the
// boundary are tested: a decimated surface's border is peeled back to the points without its
// coarse interior being cut where curvature alone takes it off the points. Returns the area
// fraction removed (0: nothing). The mesh is left as it was when what is left is not a valid
// surface.
double trim_unsupported(TriangleMeshData& mesh, const std::vector<Vec3>& points, double spacings,
                        bool border_only = false);

}  // namespace rgbmesh::fit::detail
