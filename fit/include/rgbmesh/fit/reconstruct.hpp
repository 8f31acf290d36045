#pragma once
/// \file
/// A surface through a point cloud, for the base of a fit: bounded in time and memory, checked
/// against the points, closed where the points enclose a volume and open where they do not.
///
/// Two methods, both from CGAL:
///  * Poisson surface reconstruction: a smooth, closed surface, the right base for a scan of
///    an object all round. It needs oriented normals (the file's, when usable and consistent,
///    else estimated), and it always closes the surface: where the points do not enclose a
///    volume (a scan of one side, a scene) it invents surface far from every point.
///  * advancing-front surface reconstruction: triangles through the points themselves, chosen
///    by the plausibility of their Delaunay spheres; it needs no normals and leaves open what
///    the points leave open.
/// The automatic choice (the default) tries Poisson first and keeps it when the points support
/// it: at most a small fraction of its area may lie farther than a few local spacings from
/// every point. Otherwise (an open scan, a scene), or when Poisson fails, the advancing front is
/// used, and a note says why.
///
/// Bounds: the clouds are averaged over grid cells down to a size fixed in advance (notes say
/// so), the level-set mesher runs step by step and stops at a vertex count fixed in advance
/// from the faces wanted, and every stage calls the StageControl between steps. A cloud whose
/// spacing is a large fraction of its extent cannot determine a surface and is refused.

#include <cstddef>
#include <string>
#include <vector>

#include "rgbmesh/fit/control.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fit {

enum class ReconstructionMethod {
  automatic,        ///< Poisson where the points support a closed surface, else advancing front
  poisson,          ///< closed, smooth; needs oriented normals (estimated when missing)
  advancing_front,  ///< through the points; open where the points are
};
/// "automatic", "poisson", "advancing-front".
const char* to_string(ReconstructionMethod method);
/// From the names above; false for anything else.
bool reconstruction_method_from_name(const std::string& name, ReconstructionMethod& method);

struct ReconstructionOptions {
  ReconstructionMethod method = ReconstructionMethod::automatic;
  int neighbours = 18;  ///< for normal estimation and orientation (jet fitting, MST), and the noise
  /// Points whose noise is above this fraction of their spacing (0: never) are averaged over grid
  /// cells, down to a third of it. The noise is measured about local quadric fits: CGAL's scans
  /// and meshes measure 0.01 to 0.22 (coarse meshes' vertices, whose detail is at their spacing),
  /// its noisy sphere_20k 0.61.
  double noise_to_spacing = 0.3;
  /// About this many triangles, or more where the mesher needs them (the surface is then
  /// decimated to the base's size).
  std::size_t faces = 4000;
  /// Poisson's level-set mesher criteria, as in CGAL's Poisson reconstruction: smallest facet
  /// angle (degrees), largest Delaunay ball radius and largest distance to the implicit
  /// surface, both in units of the points' average spacing (the radius bound is lowered when
  /// needed for `faces`, and both are raised so that about `faces` triangles can cover the
  /// points' extent).
  double angle = 20, radius = 30, distance = 0.375;
  /// The level-set mesher gives up past this many vertices per face wanted (a surface of F
  /// faces has about F/2 vertices): the implicit function is then far more complicated than
  /// the points (wrong normals, a function that wraps around the data) and the next method is
  /// tried.
  double max_vertices_per_face = 5;
  /// Larger clouds are averaged over grid cells down to about this many points before a
  /// method sees them (their detail is finer than any base; the fit uses every point).
  std::size_t max_points = 60000;
  /// Surface farther than this many local spacings (mean distance of a point to its 6 nearest)
  /// from the surface the points sample (each point a disc in its tangent plane, see
  /// TargetSurface) is "unsupported": nothing in the data says it is there.
  double support_spacings = 2;
  /// automatic: a Poisson surface with more than this fraction of its area unsupported is not
  /// kept (the points do not enclose a volume, or are too sparse for one). CGAL's closed scans
  /// and meshes' vertices measure 0 to 0.1% (at one spacing: 0 to 1.4%, the cow's vertices, whose
  /// spacing varies from triangle to triangle); one side of a hippo, 65%.
  double max_unsupported = 0.02;
  /// Clouds whose median spacing is more than this fraction of their bounding box's diagonal
  /// (about 500 points spread over a compact object) are refused: they do not determine a
  /// surface between them.
  double max_spacing_to_diagonal = 0.05;
  /// Advancing front: holes whose boundary is shorter than this many local spacings are gaps
  /// of the sampling, and filled (fair triangulation); longer ones are the scan's boundary.
  double fill_holes_shorter_than = 12;
};

struct Reconstruction {
  TriangleMeshData mesh;  ///< valid base (RgbMesh::from_triangles, validate()); notes: every note
  ReconstructionMethod method = ReconstructionMethod::poisson;  ///< the one used
  /// The fraction of the surface's area farther than support_spacings local spacings from every
  /// point.
  double unsupported = 0;
  double seconds = 0;
};

/// A surface through the points (see the file's description). `normals` is empty or one per
/// point; unusable ones (zero, not finite) leave their point out of Poisson's equation (a note
/// counts them), and normals that disagree in sign with their neighbours' are re-oriented
/// along a spanning tree first. InputError "reconstructing a surface from N points: ..." when
/// no method gives a surface the points support, saying what to do.
Reconstruction reconstruct_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                   const ReconstructionOptions& options = {}, const StageControl& control = {});

}  // namespace rgbmesh::fit
