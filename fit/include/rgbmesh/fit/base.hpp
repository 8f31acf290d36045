#pragma once
/// \file
/// The base mesh of a fit, built from the target when none is given: a valid 2-manifold with the
/// target's topology, reached by topology-preserving decimation of the target's faces or, for a
/// point cloud, by Poisson surface reconstruction followed by the same decimation.
///
/// Every result passes RgbMesh::from_triangles and validate(); problems are InputErrors whose
/// message names the stage ("decimating the target to 1,000 faces: ...", "reconstructing a
/// surface from 5,210 points: ..."). What was done instead of what was asked is said in notes,
/// one line each.

#include <cstddef>
#include <string>
#include <vector>

#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fit {

/// What decimation must keep.
struct Topology {
  int components = 0;
  int boundary_loops = 0;
  long euler_characteristic = 0;
  int genus = 0;  ///< summed over the components
  bool operator==(const Topology& o) const {
    return components == o.components && boundary_loops == o.boundary_loops &&
           euler_characteristic == o.euler_characteristic;
  }
  bool operator!=(const Topology& o) const { return !(*this == o); }
};

/// "1 component, genus 3, 106 boundary loops".
std::string to_string(const Topology& topology);

/// The topology of a triangle mesh, after the checks of RgbMesh::from_triangles and validate()
/// (InputError naming the problem if the mesh is not a valid base).
Topology topology_of(const TriangleMeshData& mesh);

/// "1,000": counts in messages, as the user reads them.
std::string with_thousands(std::size_t n);

/// Topology-preserving decimation to about `faces` triangles: edge collapses ordered by
/// Garland-Heckbert plane quadrics, placed at the quadric optimum, refused when they would break
/// the link condition (so no component, handle or boundary loop is lost, and triangular holes
/// stay open) or flip a triangle's normal. The result is checked (validate(), same topology as
/// the input). When the topology or the geometry stops the collapses above `faces`, the result
/// is the smallest valid mesh reached, with a note in `notes` saying so; a mesh that already has
/// at most `faces` triangles comes back unchanged, with a note. `mesh` must be a valid base (as
/// from prepare_triangle_mesh). InputError "decimating <name> to N faces: ..." otherwise.
TriangleMeshData decimate(const TriangleMeshData& mesh, std::size_t faces,
                          const std::string& name = "the target");

struct ReconstructionOptions {
  int neighbours = 18;  ///< for normal estimation and orientation (jet fitting, MST), and the noise
  /// Points whose noise is above this fraction of their spacing (0: never) are averaged over grid
  /// cells, down to a third of it. The noise is measured about local quadric fits: CGAL's scans
  /// and meshes measure 0.01 to 0.22 (coarse meshes' vertices, whose detail is at their spacing),
  /// its noisy sphere_20k 0.61.
  double noise_to_spacing = 0.3;
  /// About this many triangles, or more where the mesher needs them (the surface is then
  /// decimated to the base's size).
  std::size_t faces = 4000;
  /// Surface mesher criteria, as in CGAL's Poisson reconstruction: smallest facet angle (degrees),
  /// largest Delaunay ball radius and largest distance to the implicit surface, both in units of
  /// the points' average spacing (the radius bound is lowered when needed for `faces`).
  double angle = 20, radius = 30, distance = 0.375;
};

/// A closed surface through a point cloud: normals from the file or estimated (jet fitting, then
/// oriented along a minimum spanning tree; points that cannot be oriented are left out, with a
/// note); noisy points averaged over grid cells (a note says so); Poisson's implicit function, its
/// zero level set meshed as a closed manifold; the largest component is kept (a note says how
/// many others were dropped), checked like a base and oriented outwards. `normals` is empty or one per point.
/// InputError "reconstructing a surface from N points: ..." when it fails.
TriangleMeshData reconstruct_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                     const ReconstructionOptions& options = {});

enum class BaseSource {
  given,          ///< --base
  target,         ///< the target's own faces (no more than requested)
  decimated,      ///< the target's faces, decimated
  reconstructed,  ///< reconstructed from the target's points, then decimated
};
const char* to_string(BaseSource source);

struct BaseOptions {
  std::size_t faces = 1000;  ///< wanted triangles
  bool triangulate = false;  ///< fan-split the target's polygons (SoupOptions::triangulate)
  /// For point clouds; its `faces` is raised to 4 x `faces`, so that decimation has a finer
  /// surface to choose the base's vertices from.
  ReconstructionOptions reconstruction;
};

struct Base {
  TriangleMeshData mesh;  ///< mesh.notes: empty (the notes are below)
  BaseSource source = BaseSource::given;
  Topology topology;
  double reconstruction_seconds = 0, decimation_seconds = 0;
  std::vector<std::string> notes;  ///< every note of every stage, in order
};

/// The base for a target given as points (with optional normals) and faces (possibly none).
/// Faces that make a valid surface (prepare_triangle_mesh) are decimated; otherwise (no faces,
/// or faces that are not a manifold surface: said in one note) the surface is reconstructed
/// from the points and decimated.
Base make_base(const PolygonSoup& target, const std::vector<Vec3>& normals, const BaseOptions& options);

}  // namespace rgbmesh::fit
