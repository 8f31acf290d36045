#pragma once
/// \file
/// The base mesh of a fit, built from the target when none is given: a valid 2-manifold with the
/// target's topology, reached by topology-preserving decimation of the target's faces or, for a
/// point cloud, by surface reconstruction (reconstruct.hpp) followed by the same decimation.
///
/// Every result passes RgbMesh::from_triangles and validate(); problems are InputErrors whose
/// message names the stage ("decimating the target to 1,000 faces: ...", "reconstructing a
/// surface from 5,210 points: ..."). What was done instead of what was asked is said in notes,
/// one line each.

#include <cstddef>
#include <string>
#include <vector>

#include "rgbmesh/fit/control.hpp"
#include "rgbmesh/fit/reconstruct.hpp"
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
                          const std::string& name = "the target", const StageControl& control = {});

enum class BaseSource {
  given,          ///< --base
  target,         ///< the target's own faces (no more than requested)
  decimated,      ///< the target's faces, decimated
  reconstructed,  ///< reconstructed from the target's points, then decimated
};
const char* to_string(BaseSource source);

struct BaseOptions {
  std::size_t faces = 1000;  ///< wanted triangles
  /// How the target's faces become triangles (SoupOptions: triangulate, repair).
  SoupOptions soup;
  /// Use the target's points only, as a point cloud, even when it has faces.
  bool ignore_faces = false;
  /// For point clouds; its `faces` is raised to 4 x `faces`, so that decimation has a finer
  /// surface to choose the base's vertices from.
  ReconstructionOptions reconstruction;
};

struct Base {
  TriangleMeshData mesh;  ///< mesh.notes: empty (the notes are below)
  BaseSource source = BaseSource::given;
  Topology topology;
  double reconstruction_seconds = 0, decimation_seconds = 0;
  /// For a reconstructed base: the method used, and the fraction of the reconstructed surface's
  /// area that no point supports (reconstruct.hpp).
  ReconstructionMethod reconstruction = ReconstructionMethod::automatic;
  double unsupported = 0;
  /// An open scan's base (advancing front): the fraction of its area trimmed away where no
  /// points support it (reconstruction over parts the scan did not see), 0 when none.
  double trimmed = 0;
  std::vector<std::string> notes;  ///< every note of every stage, in order
};

/// The base for a target given as points (with optional normals) and faces (possibly none).
/// A target with faces is a surface: its faces must make a valid mesh (prepare_triangle_mesh
/// with options.soup: polygons need `triangulate`, defects `repair`; the InputError says so),
/// which is decimated. A target without faces (or with options.ignore_faces) is a point cloud:
/// its surface is reconstructed and decimated.
Base make_base(const PolygonSoup& target, const std::vector<Vec3>& normals, const BaseOptions& options,
               const StageControl& control = {});

}  // namespace rgbmesh::fit
