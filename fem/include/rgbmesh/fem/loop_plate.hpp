#pragma once
/// \file
/// The Kirchhoff plate with Loop-basis elements: D Δ²w = q on a flat domain, clamped
/// (w = 0 and ∂w/∂n = 0) on its whole boundary.
///
/// The domain is the elements of a LoopSpace built with LoopBoundary::ghost_ring: a flat mesh
/// with one more ring of triangles around it, whose outer vertices carry control values only.
/// The clamping cannot be imposed on the control values: in the box-spline space, w = 0 along
/// a lattice line forces ∂²w/∂n² = 0 there as well, which a clamped plate's bending moment
/// contradicts (the plate would lock). It is imposed weakly, by Nitsche's method for the
/// biharmonic: with the outward normal n on the boundary Γ,
///
///   a(w, v) = ∫ Δw Δv − ∫_Γ (Δw ∂ₙv + Δv ∂ₙw) + ∫_Γ (∂ₙΔw v + ∂ₙΔv w)
///             + ∫_Γ (γ₁ / h) ∂ₙw ∂ₙv + ∫_Γ (γ₃ / h³) w v,        a(w, v) = ∫ (q / D) v,
///
/// consistent (the exact solution satisfies it) and, for γ₁, γ₃ large enough, coercive. The
/// boundary terms need third derivatives of the basis (LoopBasisAt::duuu, ...).

#include <Eigen/Core>
#include <string>

#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem {

struct PlateProblem {
  std::string name = "plate";
  double rigidity = 1;  ///< D = E t³ / (12 (1 − ν²))
  ScalarField load;     ///< q, force per area
};

/// The clamped square [0, L]² under a uniform load q = 1 with D = 1: the centre deflects by
/// 0.001265319 L⁴ (Timoshenko and Woinowsky-Krieger's series, to the digits libMesh's
/// subdivision-shell example checks).
PlateProblem clamped_square_plate();
inline constexpr double kClampedSquareCentreDeflection = 0.001265319;

struct PlateOptions {
  /// The factor f of Nitsche's penalties, per element T with boundary sides: γ₁ = f C₁ and
  /// γ₃ = f C₃, where C₁ and C₃ are the largest ratios h ∫_∂T (Δv)² / ∫_T (Δv)² and
  /// h³ ∫_∂T (∂ₙΔv)² / ∫_T (Δv)² over the element's functions (small generalized eigenvalue
  /// problems). f > 2 makes the form coercive whatever the mesh (Young's inequality gives each
  /// symmetric term less than half of the element's energy), and smaller factors are refused;
  /// the default 3 keeps a margin.
  /// Larger f approaches the exact constraint, which locks: the clamped square at 16 cells a
  /// side is 6.5e-5 below the series value with 3, 8.9e-5 with 6, 2.0e-4 with 24.
  double penalty = 3;
  int edge_points = 6;  ///< Gauss points per boundary side
};

/// Solves the clamped plate. Throws InputError if the space is not flat (all control values in
/// one plane: a curved surface is a shell), has a projection or has no boundary, if the
/// boundary passes through an extraordinary vertex (the third derivatives are unbounded there),
/// and if the penalty factor is not above 2.
Solution solve_clamped_plate(const LoopSpace& space, const PlateProblem& problem,
                             const PlateOptions& options = {}, const SolveOptions& solve = {});

}  // namespace rgbmesh::fem
