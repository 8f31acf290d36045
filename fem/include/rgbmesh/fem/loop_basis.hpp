#pragma once
/// \file
/// Loop's limit functions on one triangle: the basis of Loop-basis (smooth) elements.
///
/// On a triangle of a closed triangle mesh, the limit of Loop subdivision depends only on the
/// control values of the triangle's patch: the vertices of the triangles that touch its three
/// corners (12 when all corners have valence 6, N0 + N1 + N2 - 6 in general). Where the
/// corners are regular the limit is one quartic polynomial (the box spline of the regular
/// lattice). Elsewhere it is piecewise polynomial on ever smaller triangles around the
/// extraordinary corners: a point is evaluated by subdividing the patch until the point lies
/// in a sub-triangle whose corners are regular (what Stam's eigenbasis does in closed form).
///
/// On a mesh with a boundary Loop's boundary rules apply: a boundary edge's midpoint is the
/// mean of its ends, a boundary vertex moves by its two boundary neighbours only (3/4, 1/8,
/// 1/8), so that the boundary's limit is the cubic B-spline of its vertices. A corner with
/// four neighbours (three triangles) is the boundary's regular vertex: there the limit is the
/// box spline of the patch completed across the boundary by the ghost vertices g = a + b - t,
/// one for each boundary edge ab of a triangle abt, which the boundary rules keep so at every
/// level (tests/test_loop_basis.cpp checks both against OpenSubdiv).
///
/// Sharp features (sharpness.hpp) follow the crease rules of loop_rules.hpp, as the RGB mesh's
/// surface does. An infinitely sharp edge splits the surface: a patch does not reach across
/// one where it bounds a corner's sector (a vertex with two or more such edges, the boundary's
/// counting), so that a crease vertex is a boundary vertex of each side, and the crease curve's
/// control values, shared by both sides, give both the same functions there (continuity, not
/// smoothness, across the crease). A crease vertex whose sector has three triangles is regular:
/// the box spline of the ghost completion, as on the boundary. Darts, corners, semi-sharp edges
/// and vertices are subdivided with their rules (odd blends, crease and corner masks, their
/// transitions as the sharpness decays level by level, uniformly or by Chaikin's averages).
///
/// Parameters: a point of the triangle (c0, c1, c2) is c0 + u (c1 - c0) + v (c2 - c0), with u,
/// v >= 0 and u + v <= 1, and the four triangles of one subdivision step split this domain at
/// its edges' midpoints, as the triangles of the uniform refinement do.
///
/// Everything here is topology and linear weights: the weights of the patch's control values
/// (the same for a coordinate of the surface and for a scalar field) at a point, and composite
/// quadrature rules for a patch's triangle whose points carry those weights.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "rgbmesh/sharpness.hpp"

namespace rgbmesh::fem {

/// The sharp features that the rules of a patch's corners depend on (none: a null
/// LoopPatch::creases). All sharpness values are at the patch's level.
struct LoopCreases {
  /// A sharp edge at a corner (boundary edges are infinitely sharp ones).
  struct Spoke {
    /// The patch vertex at its far end; -1 where the edge is outside the corner's sector.
    std::int32_t to = -1;
    float sharpness = 0;  ///< > 0
    /// One level down, the sharpness of its half at the far end (Chaikin's depends on the far
    /// end's other edges, which the patch does not hold).
    float far_child = 0;
    bool boundary = false;  ///< a boundary edge of the mesh
  };
  struct Corner {
    float sharpness = 0;  ///< the vertex's own
    /// Its sharp edges, in the order in which their sharpness is summed (as the mesh sums it).
    std::vector<Spoke> spokes;
    /// Its ring in the patch, counter-clockwise from corner k + 1 (open for a sector).
    std::vector<std::int32_t> ring;
    /// Two or more infinitely sharp edges cut its fan (the boundary's counting): ring is the
    /// sector that holds the central triangle.
    bool sector = false;
  };
  CreaseMethod method = CreaseMethod::uniform;
  std::array<Corner, 3> corner;

  /// Corner k follows one of Loop's plain rules at every level from this one on: smooth (no
  /// sharp edge, no sharpness of its own) or a crease between two infinitely sharp edges and
  /// nothing else sharp. Its limit then has a closed form (a box spline where its valence is
  /// regular).
  bool plain(int k) const;
  /// Corner k's rules will change over the levels (a semi-sharp edge or vertex sharpness).
  bool transient(int k) const;
};

/// The patch of one triangle: its control vertices in a canonical order and its triangles.
///
/// The order is a function of the topology alone, so that every patch with the same
/// connectivity numbers its vertices the same way and shares one table of weights: the
/// corners c0, c1, c2 first, then the other neighbours of c0 counter-clockwise from c1, then
/// those of c1 from c2, then those of c2 from c0, each vertex where it first appears.
/// On the boundary, a corner's ring is its neighbours counter-clockwise from the boundary
/// neighbour after the central triangle's edge round to the other one.
struct LoopPatch {
  std::vector<std::int32_t> vertices;         ///< the caller's vertex ids, in canonical order
  std::vector<std::array<int, 3>> triangles;  ///< local numbering, counter-clockwise, [0] = {0, 1, 2}
  std::array<int, 3> valence{};               ///< of the corners: their numbers of neighbours
  /// The corner's fan is open: on the boundary, or a sector between infinitely sharp edges.
  std::array<bool, 3> open{};
  /// The sharp features its corners' rules depend on; null where there are none (boundary
  /// edges alone need none: an open corner then takes the boundary rules).
  std::shared_ptr<const LoopCreases> creases;
  bool closed() const { return !open[0] && !open[1] && !open[2]; }
  /// Corner k is regular: valence 6 inside, 4 on the boundary (or in a sector), and plain
  /// rules (LoopCreases::plain).
  bool regular_corner(int k) const {
    const auto i = static_cast<std::size_t>(k);
    return valence[i] == (open[i] ? 4 : 6) && (!creases || creases->plain(k));
  }
  /// Every corner regular. The limit on the triangle is then one box spline (through ghost
  /// vertices beyond the boundary and beyond infinitely sharp edges).
  bool regular() const { return regular_corner(0) && regular_corner(1) && regular_corner(2); }
};

/// The neighbours of a vertex in cyclic order (either direction): `ring` returns true. For a
/// vertex on the boundary it returns false, with the ring the path of its neighbours from one
/// boundary neighbour to the other, each step a triangle (as RgbMesh::star lists them).
using RingOracle = std::function<bool(std::int32_t vertex, std::vector<std::int32_t>& ring)>;

/// The patch of the counter-clockwise triangle (c0, c1, c2). Throws InputError if a corner is
/// no triangle fan or the fans disagree (a non-manifold neighbourhood), or if the patch folds
/// onto itself (a vertex reached twice: meshes so coarse that two corners' rings overlap
/// beyond the triangle; one uniform refinement removes that).
LoopPatch gather_loop_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring);

/// A vertex's sharp features, as a patch needs them.
struct LoopVertexFeatures {
  float sharpness = 0;  ///< its own (RgbMesh::vertex_sharpness at the patch's level)
  /// Per entry of its ring: the edge's sharpness (RgbMesh::sharpness; boundary edges count as
  /// infinitely sharp whatever is given).
  std::vector<float> edges;
  /// Per entry: where its sharpness comes in sums (the mesh sums a base vertex's edges in the
  /// order of their sharp base edges); empty: ring order.
  std::vector<std::int32_t> order;
};

/// Sharp features of a mesh for gather_loop_patch: its creasing method and, for a vertex and
/// its ring (as the RingOracle gave it), its features.
struct LoopFeatures {
  CreaseMethod method = CreaseMethod::uniform;
  std::function<void(std::int32_t vertex, const std::vector<std::int32_t>& ring, LoopVertexFeatures& out)> at;
};

/// The patch on a mesh with sharp features: fans cut into sectors by infinitely sharp edges,
/// and the rules its corners need (LoopPatch::creases). The same refusals as above.
LoopPatch gather_loop_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring,
                            const LoopFeatures& features);

/// Weights of the patch's control values at one point: the limit value and its first, second
/// and third derivatives with respect to (u, v) (the third for the boundary terms of fourth-
/// order problems). At an extraordinary corner itself only the value is defined (the
/// derivatives are NaN there: the parametrization is singular).
struct LoopBasisAt {
  Eigen::VectorXd value, du, dv, duu, duv, dvv;
  Eigen::VectorXd duuu, duuv, duvv, dvvv;
};
LoopBasisAt evaluate_loop_basis(const LoopPatch& patch, double u, double v);

/// The limit value at corner k of the patch's triangle: Loop's limit mask (loop_rules.hpp); a
/// corner's own value at an infinitely sharp corner, the crease's mask on a crease; where the
/// rules still change (semi-sharp features) the patch is subdivided towards the corner until
/// they settle, and a dart's limit is that of its own rules (the fixed point of its ring's
/// subdivision, which the RGB mesh's limit positions follow, not the smooth mask).
Eigen::VectorXd loop_corner_limit(const LoopPatch& patch, int corner);

/// A quadrature rule on the parameter triangle of a patch with the basis at every point:
/// weights sum to 1/2 (the triangle's area in (u, v)). Rows are the patch's vertices, columns
/// the points (a point's weights are contiguous).
struct LoopQuadrature {
  /// The patch connectivity it is for, numbered locally (vertices 0, 1, ..., as its columns).
  LoopPatch patch;
  std::vector<double> u, v, weight;
  Eigen::MatrixXd value, du, dv, duu, duv, dvv;
  /// Functions beyond the patch's own (LoopBoundary::completed next to the boundary): rows
  /// patch.vertices.size() and on are the functions of vertices `rows` of another patch of the
  /// same triangle (the mesh completed by ghosts), subdivided by its rules. Null elsewhere.
  struct Extension {
    LoopPatch patch;
    std::vector<int> rows;
  };
  std::shared_ptr<const Extension> extension;
  std::size_t size() const { return weight.size(); }
};

/// The basis of a rule's functions at (u, v): the patch's, then its extension's (if any).
LoopBasisAt loop_rule_basis(const LoopQuadrature& rule, double u, double v);

/// The limit value of a rule's functions at corner k of its triangle (loop_corner_limit of the
/// patch, then of the extension's rows).
Eigen::VectorXd loop_rule_corner_limit(const LoopQuadrature& rule, int corner);

/// How a patch's triangle is integrated. A triangle whose corners are regular gets, with
/// `points_per_direction` = 0 (the default), the symmetric rule of 12 points exact for
/// polynomials of degree 6, or with n >= 1 a collapsed Gauss rule of n^2 points (exact to
/// degree 2n - 2; n = 4 is the default's degree with 16 points). Around an extraordinary
/// corner the limit is no polynomial: the triangle is split into its four children
/// `extraordinary_depth` times towards that corner, each regular child with the same rule, the
/// last corner child too (its points evaluated exactly). The defaults change sphere-peak's
/// errors by less than 1e-5 relative against 7 x 7 points and depth 10
/// (tests/test_loop_elements.cpp).
struct LoopQuadratureOptions {
  int points_per_direction = 0;
  int extraordinary_depth = 6;
};

/// The rule for a patch's connectivity, built once per connectivity and kept (thread-safe).
std::shared_ptr<const LoopQuadrature> loop_quadrature(const LoopPatch& patch,
                                                      const LoopQuadratureOptions& options = {});

/// The rule of a patch extended by the functions of vertices `rows` of another patch of the
/// same triangle (corners in the same order; LoopQuadrature::extension): both patches are
/// subdivided together towards the corners where either is irregular, so that the points
/// serve both.
std::shared_ptr<const LoopQuadrature> loop_quadrature(const LoopPatch& patch, const LoopPatch& extension,
                                                      const std::vector<int>& rows,
                                                      const LoopQuadratureOptions& options = {});

/// One Loop step of a patch, kept to the patch of child `child` (0-3) of its central triangle:
/// children 0-2 at corners 0-2, child 3 the middle one (its corners the midpoints of edges
/// 12, 20, 01). The child's vertices are numbered in the subdivided patch: 0..n-1 are the
/// parent's vertices (even), n and up the midpoints of its edges (odd); `origin` gives each
/// one's parents in the parent's numbering, {v, -1} for an even vertex. The child's control
/// values are from_parent times the parent's. Built once per connectivity (thread-safe).
struct LoopChildPatch {
  LoopPatch patch;
  Eigen::MatrixXd from_parent;
  std::vector<std::array<int, 2>> origin;
};
std::shared_ptr<const LoopChildPatch> loop_child_patch(const LoopPatch& parent, int child);

/// The child of the parameter triangle that holds the point (u, v) (numbered as for
/// loop_child_patch); u and v become the point's parameters in that child.
int loop_descend(double& u, double& v);

/// The rings of a small closed mesh given by its triangles (counter-clockwise), for
/// gather_loop_patch.
RingOracle triangle_rings(std::int32_t vertices, const std::vector<std::array<int, 3>>& triangles);

/// The features of a base mesh given by its tags (in RgbMesh::sharp_features' normal form),
/// for gather_loop_patch with triangle_rings: sums in the order of the tagged edges, as the mesh.
LoopFeatures tagged_features(const SharpFeatures& features);

/// Gauss-Legendre points and weights on [0, 1] (weights sum to 1).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace rgbmesh::fem
