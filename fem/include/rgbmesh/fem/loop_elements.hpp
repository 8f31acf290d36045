#pragma once
/// \file
/// Loop-basis (smooth) finite elements: the unknowns are the control values of a scalar field
/// subdivided by Loop's rules together with the surface, so that the discrete functions live
/// on the Loop limit surface itself and are C² there, except at extraordinary vertices (C¹).
/// One unknown per vertex, as P1; each triangle's functions depend on the control values of
/// its patch (loop_basis.hpp), 12 of them where its corners are regular.
///
/// On a mesh with sharp features (RgbMesh::sharp_features) the control values are subdivided by
/// the crease rules, as the surface is: the functions are continuous but not smooth across
/// infinitely sharp edges, each side's as at a boundary (LoopSpace::seams), and semi-sharp
/// features round them as they round the surface.
///
/// This first space is that of a uniformly refined mesh: every triangle green at one level L,
/// the unknowns the level-L control values of its vertices; a boundary takes a ghost ring,
/// Loop's boundary rules, or those and the functions of ghosts beyond them (LoopBoundary).
/// (The adaptive space of an RGB mesh, where each
/// inserted vertex carries a detail, builds on it: loop_adaptive.hpp.)

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/snapshot.hpp"

namespace rgbmesh::fem {

struct LoopSpace {
  int level = 0;                            ///< the level of every triangle
  std::vector<VertexHandle> vertex;         ///< DOF -> vertex
  std::vector<std::int32_t> dof_of_vertex;  ///< vertex slot -> DOF
  std::vector<Vec3> control;                ///< per DOF: the surface's control point at `level`
  struct Element {
    TriangleHandle triangle;
    std::vector<std::int32_t> dofs;              ///< the patch's vertices, in the patch's canonical order
    std::shared_ptr<const LoopQuadrature> rule;  ///< shared by the elements of one connectivity
    /// How many of `dofs` (the first) the surface sums: the patch's vertices; the rule's
    /// extension (LoopBoundary::completed) adds functions, not surface.
    std::size_t surface_dofs() const { return rule->patch.vertices.size(); }
  };
  std::vector<Element> elements;
  std::optional<Projection> projection;  ///< the exact surface the limit surface is mapped onto, if any
  /// With LoopBoundary::ghost_ring: the sides of the elements' domain, each an element and the
  /// edge of its parameter triangle from corner `edge` to corner `edge + 1` (mod 3). Empty on
  /// a closed surface.
  struct Side {
    std::size_t element = 0;
    int edge = 0;
  };
  std::vector<Side> boundary;
  /// Where two elements meet along an infinitely sharp edge (a crease, or a crease ending in a
  /// dart): there the functions are continuous but not smooth, and the residual estimator adds
  /// the jump of the co-normal derivative. One piece of such an edge per seam, as a stretch of
  /// a side of each element: from `from` to `to` along side `edge` (t of side_parameters:
  /// from corner edge to corner edge + 1). Empty on a mesh without infinitely sharp edges.
  struct Seam {
    std::array<std::size_t, 2> element{};
    std::array<int, 2> edge{};
    std::array<double, 2> from{}, to{};
  };
  std::vector<Seam> seams;

  std::size_t num_dofs() const { return vertex.size(); }
};

/// What build_loop_space does with a mesh that has a boundary.
enum class LoopBoundary {
  /// Closed surfaces only: a triangle touching the boundary is refused, named.
  refuse,
  /// The elements are the triangles whose three corners are interior vertices; the vertices
  /// beyond them (the mesh's boundary ring) carry control values only, as the ghost vertices
  /// of Cirak, Ortiz and Schröder's thin shells do. Every element keeps the interior rules and
  /// its full patch, and boundary conditions are imposed weakly on LoopSpace::boundary. The
  /// domain is the limit image of the elements, not the RGB mesh's limit surface near the
  /// boundary (which follows Loop's boundary rules): for a flat mesh both are the plane.
  ghost_ring,
  /// Every triangle is an element and every vertex a DOF, under Loop's boundary rules
  /// (loop_basis.hpp): the domain is the RGB mesh's limit surface, whose boundary is the cubic
  /// B-spline of the boundary vertices, and the functions are subdivided as the surface is.
  /// Boundary conditions are imposed weakly on LoopSpace::boundary, the mesh's boundary edges.
  /// A corner of one triangle is rounded off, as the surface is there. Next to the boundary
  /// these functions reproduce linear ones only (H1 errors fall as h^1.5).
  loop_rules,
  /// The domain, elements and functions of loop_rules, and more functions: those of ghost
  /// vertices of the mesh completed beyond its boundary by a ring of ghost triangles and
  /// subdivided by the interior rules (one ghost vertex beyond each boundary edge, and around
  /// a boundary vertex of k triangles max(1, 4 - k) triangles closing its fan). Where the
  /// boundary is regular, Loop's boundary rules are the completion's with the ghosts at
  /// a + b - t, so the space holds the completion's functions there and reproduces cubics up to
  /// the boundary; it always holds the surface's own (linear functions reproduced). The
  /// ghosts taken are those beyond an edge with an end of three triangles and none of two (the
  /// others' functions have large Laplacians where the boundary rules bend the surface's
  /// parameters: see build_loop_space). They are DOFs after the vertices (LoopSpace::vertex
  /// holds no vertex for them, `control` NaN). Not with sharp features, not for the plate.
  completed,
};

/// The Loop space of a mesh refined uniformly (every triangle green at one level). The limits
/// are computed (RgbMesh::compute_limits leaves the mesh as it was). Throws InputError naming
/// the triangle where the mesh is not uniform, where a triangle reaches a boundary (with
/// LoopBoundary::refuse), or where a triangle's patch folds onto itself (a mesh too coarse:
/// refine once).
LoopSpace build_loop_space(RgbMesh& mesh, std::optional<Projection> projection = std::nullopt,
                           const LoopQuadratureOptions& quadrature = {},
                           LoopBoundary boundary = LoopBoundary::refuse);

/// The limit surface (or its projection) at a point of an element, with the basis there:
/// position, tangents y_u, y_v, the area density |y_u × y_v| and the surface gradient of each
/// of the patch's basis functions.
struct LoopPoint {
  Vec3 x, xu, xv;
  double density = 0;
  std::vector<Vec3> gradient;
};
LoopPoint loop_point(const LoopSpace& space, std::size_t element, std::size_t point);

/// How far from singular the surface's parametrization is on an element: the smallest ratio
/// σ₂/σ₁ of the singular values of the tangent map [y_u y_v] over the element's quadrature
/// points (about 0.5 on the patch of a well-shaped triangle; 0 where the tangents are
/// parallel). Loop's limit surface is nearly singular where the control mesh has caps or
/// needles across a crease (a CAD export's T-vertex fans): there the Loop basis, smooth in the
/// parameters, is not smooth on the surface, so the residual estimator's Laplacian is large
/// and refinement converges slowly.
double loop_parametrization_ratio(const LoopSpace& space, std::size_t element);

/// The part of an estimate that lies on elements whose parametrization ratio is below `below`,
/// looked for down the largest indicators: until the regular elements met carry half of Σ η²
/// (a smaller share than half is then a lower bound), or 99% of it.
struct LoopSingularEstimate {
  double share = 0;          ///< of Σ η², on those elements
  std::size_t elements = 0;  ///< how many they are
  double ratio = 1;          ///< the smallest ratio among them
  Vec3 where;                ///< a point of the one with the largest indicator
};
LoopSingularEstimate loop_singular_estimate(const LoopSpace& space, const std::vector<double>& eta,
                                            double below = 1e-5);

/// The features of an RGB mesh refined uniformly to `level` for gather_loop_patch on its vertex
/// slots (RgbMesh::sharpness, vertex_sharpness; a base vertex's edges ranked by their sharp base
/// edges, the order in which the mesh sums them). Empty (no oracle) for a mesh without sharp
/// features. The oracle reads the mesh: use it while the mesh lives unchanged.
LoopFeatures loop_mesh_features(const RgbMesh& mesh, int level);

/// Dirichlet data on a space with a boundary, imposed weakly by Nitsche's method: the Loop
/// basis does not interpolate, and imposing u = g on the control values would also force
/// ∂²u/∂n² on the boundary (the box splines' traces). With the outward co-normal m,
///   ∫ ∇u·∇v + c u v − ∫_Γ (∂ₘu v + ∂ₘv u) + ∫_Γ (γ/h) u v = ∫ f v − ∫_Γ g ∂ₘv + ∫_Γ (γ/h) g v.
struct LoopNitscheOptions {
  /// The factor f of the penalty, per element T with Dirichlet sides: γ = f C, where C is the
  /// largest ratio h ∫_∂T (∂ₘv)² / ∫_T |∇v|² over the element's functions (a small generalized
  /// eigenvalue problem). f > 1 makes the form coercive whatever the mesh (Young's inequality),
  /// and smaller factors are refused; the default keeps a margin. Beyond that f changes the
  /// solution by the order of the discretization error.
  double penalty = 4;
  int edge_points = 6;  ///< Gauss points per boundary side
};

/// -Δu + c u = f, assembled with each element's rule and solved by options' solver (as
/// fem::solve). On a closed surface with c = 0: the zero-mean solution, for a source of zero
/// mean. On a space with a boundary (LoopBoundary::ghost_ring): u = g (problem.dirichlet,
/// zero if empty) on its boundary, by Nitsche's method, except on the sides where
/// problem.is_neumann holds at the midpoint, which take the flux ∂ₘu = h (neumann_flux); with
/// c = 0 at least one side must be Dirichlet.
Solution solve_loop(const LoopSpace& space, const Problem& problem, const SolveOptions& options = {},
                    const LoopNitscheOptions& nitsche = {});

/// Δ²u + c u = f on a closed surface (c > 0): the weak form ∫ Δ_Γu Δ_Γv + c u v = ∫ f v
/// needs functions in H², which Loop's C¹ space is (P1 and P2 are not). Solved as solve_loop.
/// InputError on a space with seams (infinitely sharp edges), where the functions are only C⁰.
Solution solve_loop_biharmonic(const LoopSpace& space, const BiharmonicProblem& problem,
                               const SolveOptions& options = {});

/// The biharmonic errors: ‖u - u_h‖, ‖∇_Γ(u - u_h)‖ and ‖Δ_Γ(u - u_h)‖ (the energy norm's
/// leading part), with the elements' rules.
struct BiharmonicErrors {
  double l2 = 0, h1 = 0, laplacian = 0;
};
BiharmonicErrors loop_biharmonic_errors(const LoopSpace& space, const Eigen::VectorXd& u,
                                        const BiharmonicProblem& problem);

/// ‖u - u_h‖ and ‖∇_Γ(u - u_h)‖ over the surface, with the elements' rules. With a projection,
/// the exact solution is evaluated at the projected points (exact geometry); without one, on
/// the limit surface itself.
ErrorNorms loop_error_norms(const LoopSpace& space, const Eigen::VectorXd& u, const ExactSolution& exact,
                            bool subtract_mean = false);

/// The Laplace-Beltrami operator of a discrete function at quadrature point `point` of an
/// element, Δ_Γ u_h = g^{ab} (∂_ab u_h - Γ^c_ab ∂_c u_h), with the Christoffel symbols of the
/// limit surface, or of its projection (whose second derivatives are taken by central
/// differences of the projection).
double loop_laplacian(const LoopSpace& space, std::size_t element, std::size_t point,
                      const Eigen::VectorXd& u);

/// The residual estimator of the smooth space: η_T² = h_T² ‖f - c u_h + Δ_Γ u_h‖²_T with h_T
/// the side of the equilateral triangle of T's area. Loop's functions are C¹, so the jumps of
/// the normal derivative across edges that P1 and P2 estimators add vanish here, except on
/// the seams (infinitely sharp edges), where ½ h_E ‖∂ₘu_h + ∂ₘ'u_h‖²_E goes to each of the two
/// elements (m, m' their outward co-normals). One indicator per element (LoopSpace::elements).
Estimate loop_residual_estimate(const LoopSpace& space, const Problem& problem, const Eigen::VectorXd& u);

/// A picture of a solution finer than the mesh: each element split `levels` times (4^levels
/// triangles, levels in [0, 6]), the surface (or its projection) and the function evaluated
/// exactly at the pieces' corners, points on shared edges once. Point data "solution", cell
/// data "element" (the element each piece belongs to). For ParaView: the function between the
/// vertices, which the values at the vertices alone do not show.
MeshSnapshot loop_refined_view(const LoopSpace& space, const Eigen::VectorXd& u, int levels);

/// The discrete function at the limit positions of the vertices (per DOF): what ParaView shows.
/// A ghost DOF (LoopBoundary::ghost_ring: a vertex that is no element's corner) has no point
/// in the domain: NaN.
Eigen::VectorXd loop_vertex_values(const LoopSpace& space, const Eigen::VectorXd& u);

/// The same values in the DOF order of a P1 mesh of the same triangles (build_surface_mesh,
/// order 1, any DofOrder): how the tools and the bindings hand a Loop solution to what shows
/// and transfers P1 data.
Eigen::VectorXd loop_values_on(const LoopSpace& space, const Eigen::VectorXd& u, const SurfaceMesh& p1);

/// One number per element (an estimate's indicators) in the triangle order of a P1 mesh of the
/// same triangles.
std::vector<double> loop_element_values_on(const LoopSpace& space, const std::vector<double>& per_element,
                                           const SurfaceMesh& p1);

}  // namespace rgbmesh::fem
