#pragma once
/// \file
/// Poisson-type problems on surfaces: -Δu + c u = f, with c >= 0.
///
/// On a closed surface with c = 0 the solution is defined up to a constant: rgbmesh returns the
/// solution of zero mean, and requires a source of zero mean (the compatibility condition,
/// checked on the surface, then enforced on the discrete load). On open surfaces, the boundary is Dirichlet (u = g) except where `is_neumann`
/// says otherwise (du/dn = h there, n the outward conormal); with c = 0 and no Dirichlet part
/// the zero-mean treatment applies, and the compatibility condition includes the flux h.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fem {

using ScalarField = std::function<double(const Vec3&)>;
using VectorField = std::function<Vec3(const Vec3&)>;
/// A scalar field evaluated at many points in one call: values[i] = f(points[i]) for
/// i < count. For fields written in an array language (a numpy function through the Python
/// package): fem calls it once per assembly or estimate with every point that computation
/// needs, from one thread, instead of once per point from several threads.
using PointValues = std::function<void(const Vec3* points, std::size_t count, double* values)>;

/// An exact solution, as a function on the exact surface: error_norms evaluates both fields
/// only at points of the surface (the lifts of quadrature points), so an extension off the
/// surface never enters the errors.
struct ExactSolution {
  ScalarField value;
  /// The surface gradient ∇_Γ u at a point of the surface: tangential to the exact surface (not
  /// the gradient of an extension to space, whose normal part would leak into the error).
  VectorField surface_gradient;
};

/// The functions of a problem (and a Projection) are called from several threads at once
/// (assembly and estimation use every core): they must be safe to call concurrently, as pure
/// functions are.
struct Problem {
  std::string name;
  double c = 0;  ///< reaction coefficient, >= 0
  ScalarField source;
  ScalarField dirichlet;                       ///< g; zero if empty
  /// f and g as PointValues, instead of `source` and `dirichlet` (at most one of each pair;
  /// InputError when both are set). The points are the same, and so are the results.
  PointValues source_values, dirichlet_values;
  std::function<bool(const Vec3&)> is_neumann;  ///< at a boundary edge's midpoint; none if empty
  ScalarField neumann_flux;                    ///< h; zero if empty
  std::optional<ExactSolution> exact;
  /// Relative tolerance of the zero-mean check |∫f + ∫h| <= tol ∫(|f| + |h|), with the
  /// integrals over the surface (lifted when a projection is known, else over the flat
  /// triangles); the discrete load is then made exactly compatible by removing its mean.
  double mean_tolerance = 1e-3;
};

// The problems with exact solutions take them as Dirichlet data, so that they also hold on an
// open patch of the sphere.

/// u = xyz on the unit sphere: a spherical harmonic of degree 3, so -Δu = 12 xyz (c = 0).
Problem sphere_harmonic();

/// u = exp(κ (x·d - 1)) on the unit sphere, a peak of width about 1/sqrt(κ) around d
/// (κ = 100 by default); with t = x·d, Δu = g''(t)(1 - t²) - 2 t g'(t) for u = g(t). Posed
/// with c = 1, so that the solution is unique without a mean condition.
Problem sphere_peak(const Vec3& d = Vec3(0.48, 0.6, 0.64), double kappa = 100.0, double c = 1.0);

/// u = cos(π x) on the surface of the unit cube [0, 1]³ whose 12 edges are infinitely sharp
/// (sharp_unit_cube, shapes.hpp), with c = 1: -Δu + u = f with f = (π² + 1) cos(π x) on the four
/// faces along x, f = u = ±1 on the faces x = 0 and x = 1 (u is constant there). u is smooth on
/// each face and its conormal derivative vanishes on every edge (∂u/∂x = 0 at x = 0, 1; the
/// other edges run along x), so u is the exact weak solution on the piecewise flat surface: the
/// test of elements and estimators across creases.
Problem cube_cosine();

/// A Gaussian source f = exp(-|x - x0|² / (2 σ²)) with c = 1, on any surface (no exact
/// solution): the problem the main job solves on its default mesh.
Problem gaussian_source(const Vec3& x0, double sigma);

/// Δ²_Γ u + c u = f on a closed surface (c > 0): a fourth-order problem, for elements whose
/// functions are in H² (Loop elements, loop_elements.hpp).
struct BiharmonicProblem {
  std::string name;
  double c = 1;
  ScalarField source;
  std::optional<ExactSolution> exact;
  ScalarField exact_laplacian;  ///< Δ_Γ u of the exact solution, for the error ‖Δ_Γ(u - u_h)‖
};

/// u = xyz on the unit sphere: a spherical harmonic of degree 3, Δu = -12 u, Δ²u = 144 u; with
/// c = 1 the source is 145 xyz.
BiharmonicProblem sphere_biharmonic();
/// u = exp(κ (x·d - 1)) on the unit sphere (sphere_peak's solution) with c = 1.
BiharmonicProblem sphere_biharmonic_peak(const Vec3& d = Vec3(0.48, 0.6, 0.64), double kappa = 20.0);

/// The built-in problems by name ("sphere-harmonic", "sphere-peak"); throws InputError listing
/// the names otherwise. The third, "gaussian", needs a centre: gaussian_source().
Problem builtin_problem(const std::string& name);
std::vector<std::string> builtin_problem_names();

}  // namespace rgbmesh::fem
