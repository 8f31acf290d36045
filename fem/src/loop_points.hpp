// The geometry and the basis of a Loop space at points of its elements (quadrature points, and
// points along sides), which the assembly and Nitsche's terms (loop_elements.cpp) and the
// error measures (loop_estimate.cpp) both evaluate: one definition, so that the estimator sees
// the surface exactly as the solve did.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem::detail {

// The geometry at one quadrature point: the point on the surface, the metric's inverse and
// the area density.
struct Frame {
  Vec3 x, xu, xv;                    // on the limit surface
  Vec3 y, yu, yv;                    // on the surface computed on (the projection's image, or the same)
  double g11 = 0, g12 = 0, g22 = 0;  // the inverse metric
  double density = 0;
  double inverse_radius = 0;  // 1 / |x| when the projection is the unit sphere's (closed-form derivatives)
  // The surface gradient of a function whose parameter derivatives are (du, dv) here.
  Vec3 gradient(double du, double dv) const { return (g11 * du + g12 * dv) * yu + (g12 * du + g22 * dv) * yv; }
};

Frame frame_at(const LoopSpace& space, const LoopSpace::Element& e, Eigen::Index p);

// The projection's derivatives at x: DP a and D²P[a, b] (closed form for the unit sphere,
// central differences otherwise).
Vec3 projected_tangent(const Projection& p, const Vec3& x, const Vec3& a);
Vec3 projection_hessian(const Projection& p, const Vec3& x, const Vec3& a, const Vec3& b);

// The Laplace-Beltrami operator at a point as weights of a function's derivatives:
// Δ_Γ u = A u_uu + B u_uv + C u_vv + D u_u + E u_v, from g^{ab} (u_ab - Γ^c_ab u_c) with
// Γ^c_ab u_c = y_ab · ∇u and ∇u = u_u t_u + u_v t_v, t_u = g^{1c} y_c, t_v = g^{2c} y_c.
struct LaplacianWeights {
  double a = 0, b = 0, c = 0, d = 0, e = 0;
};

LaplacianWeights laplacian_weights(const LoopSpace& space, const LoopSpace::Element& el, Eigen::Index p,
                                   const Frame& f);

// The source at every quadrature point when it is a batch function (one call with all the
// points); empty otherwise (problem.source is then called point by point).
struct PointSource {
  std::vector<std::size_t> first;  // per element, its first point's index
  std::vector<double> values;
  const double* of(std::size_t element) const {
    return values.empty() ? nullptr : values.data() + first[element];
  }
};

PointSource point_source(const LoopSpace& space, const PointValues& batch);

// The basis along a boundary side at the Gauss points gauss_t (in [0, 1] along the side):
// the values, the co-normal derivatives ∂ₘφ = ∇_Γφ · m with m = y_t × n / |y_t| (outward: the
// parameter triangle runs counter-clockwise about the normal n = y_u × y_v / |y_u × y_v|),
// the speed |y_t| and the point (projected, if the space has a projection).
struct SidePoint {
  Eigen::VectorXd value, dm;
  double speed = 0;
  Vec3 y;
};
std::vector<SidePoint> side_points(const LoopSpace& space, const LoopSpace::Side& side,
                                   const std::vector<double>& gauss_t);

// The Dirichlet data g at points, in one call of a batch function (zero if the problem has none).
std::vector<double> dirichlet_at(const Problem& problem, const std::vector<Vec3>& points);

// Whether a boundary side takes a flux (problem.is_neumann at its midpoint).
bool neumann_side(const LoopSpace& space, const LoopSpace::Side& side, const Problem& problem);

}  // namespace rgbmesh::fem::detail
