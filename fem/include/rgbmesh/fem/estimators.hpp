#pragma once
/// \file
/// Errors against exact solutions, and a posteriori error estimators per triangle.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/fem/work_share.hpp"

namespace rgbmesh::fem {

struct ErrorNorms {
  double l2 = 0;  ///< ‖u - u_h‖
  double h1 = 0;  ///< ‖∇(u - u_h)‖ (the energy seminorm)
};

/// The errors on the discrete surface Γ_h (the flat triangles), against the exact solution
/// lifted to it, u∘P with P the projection onto the exact surface (the standard lift of
/// surface finite elements, after Dziuk): ‖u∘P - u_h‖ and ‖∇_Γh(u∘P) - ∇_Γh u_h‖ over Γ_h, by
/// the degree-5 rule on each triangle. ∇_Γh(u∘P) at x is the surface gradient ∇_Γu at P(x)
/// pulled back through the derivative of P along the triangle's plane (central differences of
/// P); without a projection, P is the identity and ∇_Γu is projected onto the plane. With
/// subtract_mean, the exact solution is compared with its mean removed (for solutions defined
/// up to a constant).
ErrorNorms error_norms(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const ExactSolution& exact,
                       bool subtract_mean = false, const WorkShare& share = {});

/// Per-triangle indicators η_T and their total sqrt(Σ η_T²).
struct Estimate {
  std::vector<double> eta;        ///< per FE triangle
  std::vector<double> geometric;  ///< the geometric part of each η_T
  double total = 0;
};

/// The residual estimator:
/// \verbatim
///   η_T² = h_T² ‖f - c u_h + Δ_Γh u_h‖²_T + ½ Σ_{e ⊂ ∂T interior} h_e ‖[∂u_h/∂n_e]‖²_e
///          + Σ_{e ⊂ ∂T Neumann} h_e ‖h - ∂u_h/∂n_e‖²_e + η_geo,T²,
/// \endverbatim
/// (P2 takes h_T and h_e from element_scales: the same on shape-regular triangles, the width
/// of a sliver; and h_T = h_max in η_geo,T.)
/// where the jump of the conormal derivative adds the two triangles' outward conormal
/// derivatives (each in its own tangent plane), h_T is the longest chord between the corners
/// and h_e the chord of the edge, and η_geo,T = (δ_T / h_T) ‖∇u_h‖_T measures how far the
/// element is from the surface: δ_T is the largest distance from a quadrature point to its lift
/// with a projection, else the sagitta |e| θ_e / 8 of the edges, θ_e the angle between the
/// normals of the two elements at e (the curvature that the elements miss at their seams); 0 on
/// infinitely sharp creases (SurfaceMesh::crease_sides), where the surface is kinked itself.
///
/// P1: Δ_Γh u_h vanishes (u_h is linear on a flat triangle), the conormal derivatives are
/// constant along the straight edges and θ_e is the angle between the two planes.
///
/// P2: the same terms on the curved isoparametric elements. Δ_Γh u_h (laplace_beltrami) no
/// longer vanishes and balances f: without it the element term would stay near h_T ‖f‖_T,
/// falling as h while the error falls as h². The integrals over T use the element's area
/// density; the edge terms follow the quadratic curves (three-point Gauss in the edge's
/// parameter, both sides at the same points, each side's conormal in its own tangent plane
/// there). The discrete surface is continuous but kinked along the edges: without a projection
/// θ_e is the largest angle between the two elements' normals at those points, which falls as
/// h² for quadratic elements (as h for flat ones), so that δ_T ~ h³, as the distance to an
/// exact surface does. An edge node that build_surface_mesh moved to its chord's midpoint (a
/// folded element, SurfaceMesh::straightened_gap) leaves the flat element tilted against the
/// surface by about gap / across_e, which η_geo,T takes when it is larger than δ_T / h_T.
Estimate residual_estimator(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u,
                            const WorkShare& share = {});

/// How much longer than wide a triangle may be and still count as shape-regular for the P2
/// residual estimator (element_scales): its longest edge at most 3 times its smallest height
/// (an equilateral triangle: 1.15, a right isosceles one: 2, a 20°-80°-80° one: 2.9), so that
/// shape-regular meshes keep the isotropic estimator: adaptive P2 sphere-peak gives the same
/// errors as before (H1 4.20e-4 at 5·10^4 unknowns; with 2, 4.22e-4).
inline constexpr double kShapeRegularAspect = 3.0;

/// The lengths by which the P2 residual estimator weighs its terms on a triangle (its corners;
/// for a curved element, its flat triangle), with a the smallest height 2|T| / h_max and a_k the
/// height over edge k (from corner k to corner k + 1):
///  - `width` = min(h_max, 3 a), for the element residual;
///  - `across[k]` = min(|e_k|, 3 a_k), for the edge terms of edge k;
///  - `longest` = h_max.
/// On shape-regular triangles these are h_max and |e_k|, the isotropic estimator's h_T and h_e.
/// On slivers (CAD meshes have many: fans of needles, caps whose largest angle is near 180°)
/// they follow the triangle's width, as estimators for anisotropic meshes do: the element
/// residual of a sliver is dominated by u_h's curvature across it, which the error bounds
/// below only at the scale of the width (h_min ‖R‖_T ≤ C ‖∇e‖ by the bubble argument with the
/// inverse estimate on a sliver; with h_max the indicator grows with the aspect ratio, 100 to
/// 700 for the caps of CGAL's boeing.off, which then carried most of the estimate while their
/// error was small), and an edge's jump is weighed by the height over the edge, the distance
/// across which it spreads into the element.
struct ElementScales {
  double width = 0, longest = 0;
  std::array<double, 3> across{};
};
ElementScales element_scales(const Vec3& p0, const Vec3& p1, const Vec3& p2);

/// Δ_Γh u_h, the Laplace–Beltrami operator of the discrete function u on the element, at a
/// point of its reference triangle (barycentric coordinates λ): 0 for P1 (linear on a flat
/// triangle). P2: with X(ξ) the quadratic element over ξ = (λ1, λ2), X_i = ∂X/∂ξ_i, the metric
/// g_ij = X_i · X_j and the Christoffel symbols Γ^k_ij = g^kl (X_l · X_ij),
/// Δu = g^ij (u_ij - Γ^k_ij u_k); as Γ^k_ij u_k = ∇_Γh u · X_ij, this is
/// g^ij (u_ij - ∇_Γh u · X_ij). Exact on flat affine elements for quadratic u; on curved ones
/// the X_ij carry the curvature (for u the coordinate functions it gives the element's mean
/// curvature vector).
double laplace_beltrami(const SurfaceMesh& mesh, std::size_t triangle, const std::array<double, 3>& lambda,
                        const Eigen::VectorXd& u);

/// The Zienkiewicz-Zhu estimator: η_T = ‖G_h - ∇u_h‖_T, with G_h the piecewise linear field of
/// area-weighted averages of ∇u_h at the vertices, projected onto each triangle's plane.
Estimate zz_estimator(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const WorkShare& share = {});

/// An a posteriori error estimator: what the adaptive loop (adapt::AdaptOptions::estimator)
/// asks for the indicators of a solved cycle. Derive from it to drive adaptation by your own
/// indicators, as MFEM's ErrorEstimator is used; make_estimator gives the built-in ones by name.
class ErrorEstimator {
 public:
  virtual ~ErrorEstimator() = default;
  /// Per-triangle indicators η_T of the solution u of `problem` on `mesh` (one per FE
  /// triangle) and their total sqrt(Σ η_T²). On several processes (share.part not empty)
  /// compute the triangles for which share.computes(t) holds and fill in the others with
  /// share.gather, as the built-in estimators do; the adaptive loop forms the total of a
  /// distributed mesh itself. Called from one thread at a time.
  virtual Estimate estimate(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u,
                            const WorkShare& share) const = 0;
};

/// residual_estimator as an ErrorEstimator.
class ResidualEstimator final : public ErrorEstimator {
 public:
  Estimate estimate(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u,
                    const WorkShare& share) const override;
};

/// zz_estimator as an ErrorEstimator (the problem is not used).
class ZzEstimator final : public ErrorEstimator {
 public:
  Estimate estimate(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u,
                    const WorkShare& share) const override;
};

/// One row of the table of estimators by name, which the command line's --estimator and
/// Python's estimator= both read (adding an estimator: its class, and a row here).
struct NamedEstimator {
  const char* name;
  const char* description;
  std::shared_ptr<const ErrorEstimator> (*make)();
};
/// Every built-in estimator: "residual", "zz".
const std::vector<NamedEstimator>& estimator_table();
/// The estimator of that name; InputError naming the choices otherwise.
std::shared_ptr<const ErrorEstimator> make_estimator(const std::string& name);

}  // namespace rgbmesh::fem
