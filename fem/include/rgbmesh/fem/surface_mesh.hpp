#pragma once
/// \file
/// The finite-element view of an RGB mesh: triangles whose nodes lie on the surface.
///
/// P1: one degree of freedom per mesh vertex, flat triangles; P2: one more per edge, the
/// triangles curved through their six nodes (build_surface_mesh). The vertices sit at their Loop limit positions
/// (the default: the mesh is then inscribed in the limit surface), or at the image of the
/// limit positions under a projection onto a known surface (the exact-geometry mode, used to
/// verify the solver against exact solutions; the unit sphere is built in). With a projection,
/// functions of the surface (sources, exact solutions) are evaluated at the projection of each
/// quadrature point, the standard lift of surface finite elements.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::fem {

/// A map from points near the surface onto it.
using Projection = std::function<Vec3(const Vec3&)>;

/// p / |p|: the unit sphere centred at the origin.
Vec3 project_to_unit_sphere(const Vec3& p);

/// The geometries the tool and Python offer by name (named_row): "loop", the Loop limit
/// surface itself (no projection: an empty function), and "sphere", its projection onto the
/// unit sphere (project_to_unit_sphere).
const std::vector<Named<Projection>>& geometry_table();

struct SurfaceMesh {
  /// 1: linear elements on flat triangles (P1); 2: isoparametric quadratic elements (P2), six
  /// nodes per triangle on the surface, the triangles curved through them.
  int order = 1;
  std::vector<Vec3> points;                            ///< one per DOF: the vertices, then (P2) the edge nodes
  std::vector<std::array<std::int32_t, 3>> triangles;  ///< counter-clockwise corners
  /// P2: per triangle, the DOF of the node on edge k (from corner k to corner k+1).
  std::vector<std::array<std::int32_t, 3>> edge_nodes;
  std::vector<VertexHandle> vertex;                    ///< DOF -> RGB vertex
  std::vector<TriangleHandle> triangle;                ///< FE triangle -> RGB triangle
  std::vector<std::int32_t> dof_of_vertex;             ///< RGB vertex slot -> DOF (-1 if none)
  /// Boundary edges as DOF pairs, oriented as in their triangle, with that triangle.
  struct BoundaryEdge {
    std::int32_t a, b, triangle;
    std::int32_t middle = -1;  ///< P2: the edge's node
  };
  std::vector<BoundaryEdge> boundary_edges;
  /// Per triangle, bit k set where its edge k (corner k to corner k+1) lies on an infinitely
  /// sharp crease of the surface (sharpness.hpp): the surface itself is kinked there, which the
  /// estimators' geometric term must not count as a distance to it. Empty without creases.
  std::vector<std::uint8_t> crease_sides;
  bool on_crease(std::size_t t, int edge) const {
    return !crease_sides.empty() && ((crease_sides[t] >> edge) & 1) != 0;
  }
  std::optional<Projection> projection;  ///< set in exact-geometry mode
  /// P2: per DOF, how far an edge node that build_surface_mesh moved to its chord's midpoint
  /// (to keep an element from folding: kMinCurvedJacobian) lies from the surface point it stood
  /// for; 0 for every other DOF. Empty when no node was moved. The residual estimator counts
  /// this gap as distance between the discrete and the exact surface.
  std::vector<double> straightened_gap;

  std::size_t num_dofs() const { return points.size(); }
  /// The point of the surface that x on the flat triangles stands for.
  Vec3 lift(const Vec3& x) const { return projection ? (*projection)(x) : x; }
  /// The derivative of the lift at x along the plane of a flat triangle (unit normal n, size a
  /// length of the triangle's scale): an orthonormal basis (e1, e2) of the plane and the images
  /// dP e1, dP e2 of the basis under the derivative of the projection P, by central
  /// differences (e1, e2 themselves without a projection).
  struct LiftTangents {
    Vec3 e1, e2;    ///< orthonormal, in the triangle's plane
    Vec3 de1, de2;  ///< dP e1, dP e2: tangent to the surface at lift(x)
  };
  LiftTangents lift_tangents(const Vec3& x, const Vec3& n, double size) const;
  /// The ratio of the surface's area element to the flat triangle's at x: |dP e1 × dP e2|
  /// (lift_tangents), 1 without a projection.
  double lift_area_factor(const Vec3& x, const Vec3& n, double size) const;
  double total_area() const;
};

/// The FE mesh of the RGB mesh's current triangles. Vertices are placed at their limit
/// positions (RgbMesh::compute_limits, which leaves the mesh as it was), then projected if a
/// projection is given. Throws InputError naming the triangle if one is degenerate (zero area).
/// Order 2 adds a node on every edge: with a projection, the projection of the edge's midpoint
/// (isoparametric elements on the exact surface); without one, the limit position of the
/// vertex that splitting the edge would insert (RgbMesh::split_limits; the mesh is left as it
/// was), so that all six nodes lie on the Loop limit surface; a red edge (no subdivision vertex
/// splits it) gets the midpoint of its ends.
///
/// The numbering (DofOrder): `canonical` (the default) numbers the vertices and triangles in
/// canonical_vertex_order and canonical_triangle_order, each triangle's corners from its
/// lowest-numbered one, so that the system, and with it the solution, is the same bit for bit
/// for the same mesh with other handles (a restored or resumed mesh); `mesh` keeps the order of
/// RgbMesh::vertices() and triangles() and their stored corners, which arrays taken from the
/// mesh share (the Python module's Solution).
enum class DofOrder { canonical, mesh };
SurfaceMesh build_surface_mesh(RgbMesh& mesh, std::optional<Projection> projection = std::nullopt, int order = 1,
                               DofOrder dof_order = DofOrder::canonical);

/// The smallest Jacobian, relative to that of its flat triangle, that build_surface_mesh
/// accepts for a curved P2 element (curved_jacobian_ratio). Below it the quadratic map through
/// the six nodes folds over, or nearly: its area element vanishes inside the element, the
/// metric's inverse blows up there and with it the element's stiffness and its Laplace-Beltrami
/// residual (measured on CGAL's boeing.off: 357 of 2,564 elements folded, residuals 10^9 times
/// their neighbours'). Such an element gets straight edges instead (see build_surface_mesh).
/// 1/4 keeps the projected area element within a factor 4 of the flat triangle's. Irregular
/// base meshes have such elements too: 56 of the cow's 5,804 fold, 547 fall below 1/4 (1,307
/// of its 8,706 edges are straightened); the sphere's meshes have none.
inline constexpr double kMinCurvedJacobian = 0.25;

/// The smallest value over a curved P2 triangle (six nodes: the corners, then the nodes of
/// edges 0-1, 1-2, 2-0) of det D(P∘X) / det DX_A: the Jacobian of the element's quadratic map X
/// projected onto the plane of its corners (P), relative to the affine map X_A through the
/// corners alone; 1 for straight edges. Exact: the Jacobian is a quadratic polynomial on the
/// reference triangle, minimized over its corners, its edges and its interior. Negative where
/// the element folds over its flat triangle (not a graph over it), 0 where it is degenerate.
/// This is the "scaled Jacobian" by which high-order meshers judge curved elements valid.
double curved_jacobian_ratio(const std::array<Vec3, 6>& nodes);

/// Geometry of one flat triangle: area, unit normal and the (constant) gradients of its three
/// barycentric coordinates.
struct TriangleGeometry {
  double area = 0;
  Vec3 normal;
  std::array<Vec3, 3> grad;
};
TriangleGeometry triangle_geometry(const Vec3& p0, const Vec3& p1, const Vec3& p2);

/// An element at a point of its reference triangle (barycentric coordinates λ of the corners):
/// the position on the discrete surface, the unit normal there, the area density (integrals
/// over the element are Σ weight · density · f over a rule whose weights sum to 1: for a flat
/// triangle the density is its area) and the nodal basis functions with their surface
/// gradients (3 for P1; 6 for P2: the corners, then the nodes of edges 0-1, 1-2, 2-0).
struct ElementPoint {
  Vec3 x, normal;
  double density = 0;
  int nodes = 3;
  std::array<std::int32_t, 6> dof{};
  std::array<double, 6> value{};
  std::array<Vec3, 6> gradient{};
};
ElementPoint element_point(const SurfaceMesh& mesh, std::size_t triangle, const std::array<double, 3>& lambda);

/// A degree-5 rule on triangles (7 points; exact for polynomials of degree 5): barycentric
/// coordinates and weights that sum to 1 (multiply by the area).
struct QuadraturePoint {
  std::array<double, 3> barycentric;
  double weight;
};
const std::array<QuadraturePoint, 7>& triangle_quadrature();

}  // namespace rgbmesh::fem
