#pragma once
/// \file
/// Errors against exact solutions, and a posteriori error estimators per triangle.

#include <Eigen/Core>
#include <vector>

#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"

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
                       bool subtract_mean = false);

/// Per-triangle indicators η_T and their total sqrt(Σ η_T²).
struct Estimate {
  std::vector<double> eta;        ///< per FE triangle
  std::vector<double> geometric;  ///< the geometric part of each η_T
  double total = 0;
};

/// The residual estimator:
/// \verbatim
///   η_T² = h_T² ‖f - c u_h‖²_T + ½ Σ_{e ⊂ ∂T interior} h_e ‖[∂u_h/∂n_e]‖²_e
///          + Σ_{e ⊂ ∂T Neumann} h_e ‖h - ∂u_h/∂n_e‖²_e + η_geo,T²,
/// \endverbatim
/// where the jump of the conormal derivative adds the two triangles' outward conormal
/// derivatives (each in its own plane), and η_geo,T = (δ_T / h_T) ‖∇u_h‖_T measures how far the
/// flat triangle is from the surface: δ_T is the largest distance from a quadrature point to
/// its lift with a projection, else the sagitta |e| θ_e / 8 of the edges, θ_e the angle
/// between the normals of the two triangles at e (the curvature that flat triangles miss).
Estimate residual_estimator(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u);

/// The Zienkiewicz-Zhu estimator: η_T = ‖G_h - ∇u_h‖_T, with G_h the piecewise linear field of
/// area-weighted averages of ∇u_h at the vertices, projected onto each triangle's plane.
Estimate zz_estimator(const SurfaceMesh& mesh, const Eigen::VectorXd& u);

}  // namespace rgbmesh::fem
