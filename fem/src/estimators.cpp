#include "rgbmesh/fem/estimators.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "edge_key.hpp"
#include "for_each_index.hpp"
#include "rgbmesh/errors.hpp"
#include "source_samples.hpp"

namespace rgbmesh::fem {

namespace {

Vec3 at(const std::array<double, 3>& l, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return l[0] * p0 + l[1] * p1 + l[2] * p2;
}

Vec3 tangential(const Vec3& v, const Vec3& n) { return v - dot(v, n) * n; }

// ∇u_h on a triangle: Σ u_i ∇λ_i.
Vec3 gradient(const TriangleGeometry& g, const std::array<std::int32_t, 3>& t, const Eigen::VectorXd& u) {
  return u[t[0]] * g.grad[0] + u[t[1]] * g.grad[1] + u[t[2]] * g.grad[2];
}

double longest_edge(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return std::max({distance(p0, p1), distance(p1, p2), distance(p2, p0)});
}

using detail::edge_key;

// One side of an edge: a triangle and its local edge k (from corner k to corner k + 1).
struct Side {
  std::int32_t triangle;
  int edge;
};

// The triangles that the terms of this process's own triangles read (WorkShare): those with
// at least `corners` corners at vertices of its own triangles (2: its own and their neighbours
// across edges; 1: every triangle around their corners). Empty, meaning all, on one process.
std::vector<char> needed_triangles(const SurfaceMesh& mesh, const WorkShare& share, int corners) {
  if (share.part.empty()) return {};
  const std::size_t nt = mesh.triangles.size();
  std::vector<char> near(mesh.num_dofs(), 0), needed(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
    if (share.computes(t))
      for (const std::int32_t v : mesh.triangles[t]) near[v] = 1;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& c = mesh.triangles[t];
    needed[t] = near[c[0]] + near[c[1]] + near[c[2]] >= corners;
  }
  return needed;
}
bool among(const std::vector<char>& triangles, std::size_t t) { return triangles.empty() || triangles[t] != 0; }

// The interior edges between the given triangles (empty: all), each with its two sides, in the
// order in which a sweep over the triangles meets their second side (the order the estimators
// add the edges' terms in; a subset of the triangles keeps the order of the edges it has).
std::vector<std::array<Side, 2>> interior_edges(const SurfaceMesh& mesh, const std::vector<char>& triangles = {}) {
  const std::size_t nt = mesh.triangles.size();
  std::vector<std::array<Side, 2>> edges;
  edges.reserve(nt * 3 / 2);
  std::unordered_map<std::uint64_t, Side> first;
  first.reserve(nt * 2);
  for (std::size_t i = 0; i < nt; ++i) {
    if (!among(triangles, i)) continue;
    const auto& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const Side side{static_cast<std::int32_t>(i), k};
      const auto [it, inserted] = first.try_emplace(edge_key(t[k], t[(k + 1) % 3]), side);
      if (!inserted) edges.push_back({it->second, side});
    }
  }
  return edges;
}

// u_h and its surface gradient at a point of an element.
struct Evaluated {
  double value = 0;
  Vec3 gradient;
};
Evaluated evaluate(const ElementPoint& p, const Eigen::VectorXd& u) {
  Evaluated e;
  for (int i = 0; i < p.nodes; ++i) {
    e.value += p.value[i] * u[p.dof[i]];
    e.gradient += u[p.dof[i]] * p.gradient[i];
  }
  return e;
}

// Each triangle's geometry and the (constant) gradient of u_h on it.
// Each needed triangle's geometry and the (constant) gradient of u_h on it, stored for those
// triangles only (on several processes a small part of the mesh).
class TriangleFields {
 public:
  TriangleFields(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const std::vector<char>& triangles) {
    const std::size_t nt = mesh.triangles.size();
    std::size_t count = nt;
    if (!triangles.empty()) {
      slot_.assign(nt, -1);
      count = 0;
      for (std::size_t t = 0; t < nt; ++t)
        if (triangles[t]) slot_[t] = static_cast<std::int32_t>(count++);
    }
    geo_.resize(count);
    grad_.resize(count);
    detail::for_each_index(nt, [&](std::size_t t) {
      if (!among(triangles, t)) return;
      const auto& c = mesh.triangles[t];
      const std::size_t k = at(t);
      geo_[k] = triangle_geometry(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]]);
      grad_[k] = gradient(geo_[k], c, u);
    });
  }
  const TriangleGeometry& geo(std::size_t t) const { return geo_[at(t)]; }
  const Vec3& grad(std::size_t t) const { return grad_[at(t)]; }

 private:
  std::size_t at(std::size_t t) const { return slot_.empty() ? t : static_cast<std::size_t>(slot_[t]); }
  std::vector<std::int32_t> slot_;  // triangle -> its place (empty: all triangles, in order)
  std::vector<TriangleGeometry> geo_;
  std::vector<Vec3> grad_;
};

// The reference derivatives of the six P2 basis functions (corners, then the nodes of edges
// 0-1, 1-2, 2-0; as in element_point) in ξ = (λ1, λ2), λ0 = 1 - ξ1 - ξ2: the first ones at λ
// and the second ones, constant for quadratics.
struct QuadraticShapeDerivatives {
  std::array<double, 6> d1, d2;          // ∂/∂ξ1, ∂/∂ξ2
  std::array<double, 6> d11, d12, d22;  // ∂²/∂ξ1², ∂²/∂ξ1∂ξ2, ∂²/∂ξ2²
};
QuadraticShapeDerivatives quadratic_shape_derivatives(const std::array<double, 3>& l) {
  return {{-(4 * l[0] - 1), 4 * l[1] - 1, 0.0, 4 * (l[0] - l[1]), 4 * l[2], -4 * l[2]},
          {-(4 * l[0] - 1), 0.0, 4 * l[2] - 1, -4 * l[1], 4 * l[1], 4 * (l[0] - l[2])},
          {4, 4, 0, -8, 0, 0},
          {4, 0, 0, -4, 4, -4},
          {4, 0, 4, 0, 0, -8}};
}

// The estimators know linear and quadratic elements (build_surface_mesh makes no others; a
// hand-made mesh of another order gets a clear error instead of wrong numbers).
void require_order_1_or_2(const SurfaceMesh& mesh, const char* what) {
  if (mesh.order != 1 && mesh.order != 2)
    throw std::invalid_argument(std::string(what) + ": only for elements of order 1 and 2, not order " +
                                std::to_string(mesh.order));
}

// η_T from η_T² and the total; on several processes, the other processes' triangles first
// (one message: each triangle's square and geometric part side by side).
Estimate finish(std::vector<double> eta_squared, std::vector<double> geometric, const WorkShare& share) {
  if (share.gather && !share.part.empty()) {
    const std::size_t nt = eta_squared.size();
    std::vector<double> both(2 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
      both[2 * t] = eta_squared[t];
      both[2 * t + 1] = geometric[t];
    }
    share.gather(both.data(), 2, share.part);
    for (std::size_t t = 0; t < nt; ++t) {
      eta_squared[t] = both[2 * t];
      geometric[t] = both[2 * t + 1];
    }
  }
  Estimate e;
  double sum = 0;
  e.eta.resize(eta_squared.size());
  for (std::size_t i = 0; i < eta_squared.size(); ++i) {
    sum += eta_squared[i];
    e.eta[i] = std::sqrt(eta_squared[i]);
  }
  e.total = std::sqrt(sum);
  e.geometric = std::move(geometric);
  return e;
}

}  // namespace

ErrorNorms error_norms(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const ExactSolution& exact,
                       bool subtract_mean, const WorkShare& share) {
  const auto& rule = triangle_quadrature();
  const std::size_t nt = mesh.triangles.size();
  double mean = 0;
  if (subtract_mean) {
    std::vector<double> integral_area(2, 0.0);
    for (std::size_t t = 0; t < nt; ++t) {
      if (!share.computes(t)) continue;
      for (const auto& q : rule) {
        const ElementPoint p = element_point(mesh, t, q.barycentric);
        integral_area[0] += q.weight * p.density * exact.value(mesh.lift(p.x));
        integral_area[1] += q.weight * p.density;
      }
    }
    if (share.sum) share.sum(integral_area.data(), integral_area.size());
    mean = integral_area[0] / integral_area[1];
  }
  // Each triangle's share on every core, summed in triangle order (the numbers of one thread).
  std::vector<std::array<double, 2>> terms(nt, {0.0, 0.0});
  detail::for_each_index(nt, [&](std::size_t t) {
    if (!share.computes(t)) return;
    double& l2 = terms[t][0];
    double& h1 = terms[t][1];
    const auto& c = mesh.triangles[t];
    const double size = longest_edge(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]]);
    for (const auto& q : rule) {
      const ElementPoint p = element_point(mesh, t, q.barycentric);
      const auto [uh, grad_h] = evaluate(p, u);
      const Vec3 y = mesh.lift(p.x);
      const double d = exact.value(y) - mean - uh;
      // The gradient on the element of the lifted solution u∘P: along each direction e of its
      // tangent plane, the derivative is ∇_Γu(P(x)) · dP e (the chain rule; ∇_Γu is
      // tangential, so only the tangential part of dP e counts).
      const SurfaceMesh::LiftTangents lt = mesh.lift_tangents(p.x, p.normal, size);
      const Vec3 grad_exact = exact.surface_gradient(y);
      const Vec3 dg = dot(grad_exact, lt.de1) * lt.e1 + dot(grad_exact, lt.de2) * lt.e2 - grad_h;
      const double w = q.weight * p.density;
      l2 += w * d * d;
      h1 += w * dot(dg, dg);
    }
  });
  std::vector<double> sums(2, 0.0);
  for (const auto& [a, b] : terms) {
    sums[0] += a;
    sums[1] += b;
  }
  if (share.sum) share.sum(sums.data(), sums.size());
  return {std::sqrt(sums[0]), std::sqrt(sums[1])};
}

ElementScales element_scales(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const std::array<double, 3> edge = {distance(p0, p1), distance(p1, p2), distance(p2, p0)};
  const double twice_area = norm(cross(p1 - p0, p2 - p0));
  ElementScales s;
  s.longest = std::max({edge[0], edge[1], edge[2]});
  s.width = std::min(s.longest, kShapeRegularAspect * twice_area / s.longest);
  for (int k = 0; k < 3; ++k) s.across[k] = std::min(edge[k], kShapeRegularAspect * twice_area / edge[k]);
  return s;
}

double laplace_beltrami(const SurfaceMesh& mesh, std::size_t triangle, const std::array<double, 3>& lambda,
                        const Eigen::VectorXd& u) {
  if (mesh.order == 1) return 0.0;
  require_order_1_or_2(mesh, "laplace_beltrami");
  const auto& c = mesh.triangles[triangle];
  const auto& e = mesh.edge_nodes[triangle];
  const std::array<std::int32_t, 6> dof = {c[0], c[1], c[2], e[0], e[1], e[2]};
  const QuadraticShapeDerivatives d = quadratic_shape_derivatives(lambda);
  Vec3 x1, x2, x11, x12, x22;
  double u1 = 0, u2 = 0, u11 = 0, u12 = 0, u22 = 0;
  for (int i = 0; i < 6; ++i) {
    const Vec3& node = mesh.points[dof[i]];
    const double v = u[dof[i]];
    x1 += d.d1[i] * node;
    x2 += d.d2[i] * node;
    x11 += d.d11[i] * node;
    x12 += d.d12[i] * node;
    x22 += d.d22[i] * node;
    u1 += d.d1[i] * v;
    u2 += d.d2[i] * v;
    u11 += d.d11[i] * v;
    u12 += d.d12[i] * v;
    u22 += d.d22[i] * v;
  }
  const double g11 = dot(x1, x1), g12 = dot(x1, x2), g22 = dot(x2, x2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0)) throw std::runtime_error("laplace_beltrami: a curved triangle is degenerate at the point");
  const double i11 = g22 / det, i12 = -g12 / det, i22 = g11 / det;  // g^ij
  // Γ^k_ij u_k = (g^kl u_k) (X_l · X_ij) = ∇_Γh u · X_ij: the Christoffel terms in one product.
  const Vec3 grad = (i11 * u1 + i12 * u2) * x1 + (i12 * u1 + i22 * u2) * x2;
  return i11 * (u11 - dot(grad, x11)) + 2 * i12 * (u12 - dot(grad, x12)) + i22 * (u22 - dot(grad, x22));
}

namespace {

// A point of the curved edge k of a P2 element (from corner k to corner k + 1, the quadratic
// curve through the corners and the edge's node) at parameter s in [0, 1]: the point, the
// element's unit normal there, the length element |dX/ds| and u_h's derivative along the
// outward unit conormal, the edge's tangent turned in the element's tangent plane (the tangent
// lies in that plane: the edge is a curve of the element).
struct CurvedEdgePoint {
  Vec3 x, normal;
  double speed = 0, flux = 0;
};
CurvedEdgePoint curved_edge_point(const SurfaceMesh& mesh, const Eigen::VectorXd& u, std::size_t t, int k,
                                  double s) {
  std::array<double, 3> l{};
  l[k] = 1 - s;
  l[(k + 1) % 3] = s;
  const ElementPoint p = element_point(mesh, t, l);
  const Vec3 &a = mesh.points[mesh.triangles[t][k]], &b = mesh.points[mesh.triangles[t][(k + 1) % 3]];
  const Vec3& m = mesh.points[mesh.edge_nodes[t][k]];
  const Vec3 tangent = (4 * s - 3) * a + (4 * s - 1) * b + (4 - 8 * s) * m;
  const Vec3 conormal = cross(tangent, p.normal);
  const Vec3 grad = evaluate(p, u).gradient;
  return {p.x, p.normal, norm(tangent), dot(grad, conormal) / norm(conormal)};
}

// The jumps across interior edges, as both residual estimators add them: each edge's terms on
// every core (edge_term(n) gives ∫_e [∂u_h/∂μ]² ds in the estimator's weighting, and the
// sagitta |e| θ_e / 8), then added to both sides' triangles in edge order, the numbers of one
// thread: weight(triangle, local edge) times the first to η², and without a projection the
// sagitta to δ (the projection's distance replaces it).
template <class EdgeTerm, class Weight>
void add_interior_jumps(const SurfaceMesh& mesh, const WorkShare& share,
                        const std::vector<std::array<Side, 2>>& edges, const EdgeTerm& edge_term,
                        const Weight& weight, std::vector<double>& eta2, std::vector<double>& delta) {
  std::vector<std::array<double, 2>> terms(edges.size(), {0.0, 0.0});
  detail::for_each_index(edges.size(), [&](std::size_t n) {
    if (share.computes(static_cast<std::size_t>(edges[n][0].triangle)) ||
        share.computes(static_cast<std::size_t>(edges[n][1].triangle)))
      terms[n] = edge_term(n);
  });
  for (std::size_t n = 0; n < edges.size(); ++n) {
    for (const Side& side : edges[n]) {
      const auto t = static_cast<std::size_t>(side.triangle);
      if (!share.computes(t)) continue;
      eta2[t] += weight(t, side.edge) * terms[n][0];
      if (!mesh.projection) delta[t] = std::max(delta[t], terms[n][1]);
    }
  }
}

// Three-point Gauss on [0, 1]: exact for quintics along the edge's parameter.
constexpr double kGaussOffset = 0.3872983346207416885;  // ½ sqrt(3/5)
constexpr std::array<std::array<double, 2>, 3> kEdgeGauss = {
    {{0.5 - kGaussOffset, 5.0 / 18}, {0.5, 8.0 / 18}, {0.5 + kGaussOffset, 5.0 / 18}}};

// The residual estimator of P2 (see the header): the element terms and the edge jumps on every
// core into per-triangle and per-edge slots, summed serially in triangle and edge order (the
// numbers of one thread).
Estimate residual_estimator_quadratic(const SurfaceMesh& mesh, const Problem& problem,
                                      const Eigen::VectorXd& u, const WorkShare& share) {
  const std::size_t nt = mesh.triangles.size();
  const auto& rule = triangle_quadrature();
  std::vector<ElementScales> scale(nt);
  std::vector<double> eta2(nt, 0.0), energy(nt, 0.0), delta(nt, 0.0), tilt(nt, 0.0), geometric(nt, 0.0);
  const detail::SourceSamples source(mesh, problem, detail::SamplePoints::element, share);
  // The triangles' widths (element_scales), for the needed ones: the edge terms read both sides'.
  const std::vector<char> needed = needed_triangles(mesh, share, 2);
  detail::for_each_index(nt, [&](std::size_t t) {
    if (!among(needed, t)) return;
    const auto& c = mesh.triangles[t];
    scale[t] = element_scales(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]]);
  });
  // Element residuals f - c u_h + Δ_Γh u_h, ‖∇u_h‖²_T and (with a projection) the distance to
  // the surface.
  detail::for_each_index(nt, [&](std::size_t t) {
    if (!share.computes(t)) return;
    double r2 = 0;
    for (std::size_t n = 0; n < rule.size(); ++n) {
      const auto& q = rule[n];
      const ElementPoint p = element_point(mesh, t, q.barycentric);
      const auto [uh, grad] = evaluate(p, u);
      const Vec3 lifted = mesh.lift(p.x);
      const double r = source.at(t, n, lifted) - problem.c * uh +
                       laplace_beltrami(mesh, t, q.barycentric, u);
      const double w = q.weight * p.density;
      r2 += w * r * r;
      energy[t] += w * dot(grad, grad);
      if (mesh.projection) delta[t] = std::max(delta[t], distance(p.x, lifted));
    }
    eta2[t] = scale[t].width * scale[t].width * r2;
  });
  const std::vector<std::array<Side, 2>> edges = interior_edges(mesh, needed);
  // Per edge: ∫_e [∂u_h/∂μ]² ds, which each side weighs with ½ its width across the edge, and
  // the sagitta |e| θ_e / 8. The second side runs the other way along the edge, so its
  // parameter 1 - s meets the first side's s at the same point.
  add_interior_jumps(
      mesh, share, edges,
      [&](std::size_t n) -> std::array<double, 2> {
        const auto& [a, b] = edges[n];
        const auto ta = static_cast<std::size_t>(a.triangle), tb = static_cast<std::size_t>(b.triangle);
        double integral = 0, theta = 0;
        for (const auto& [s, w] : kEdgeGauss) {
          const CurvedEdgePoint pa = curved_edge_point(mesh, u, ta, a.edge, s);
          const CurvedEdgePoint pb = curved_edge_point(mesh, u, tb, b.edge, 1 - s);
          const double jump = pa.flux + pb.flux;
          integral += w * pa.speed * jump * jump;
          if (!mesh.on_crease(ta, a.edge))  // a crease's kink is the surface's own
            theta = std::max(theta, std::acos(std::clamp(dot(pa.normal, pb.normal), -1.0, 1.0)));
        }
        const auto& c = mesh.triangles[ta];
        const double len = distance(mesh.points[c[a.edge]], mesh.points[c[(a.edge + 1) % 3]]);
        return {integral, len * theta / 8.0};
      },
      [&](std::size_t t, int edge) { return 0.5 * scale[t].across[edge]; }, eta2, delta);
  // An edge node that build_surface_mesh moved to its chord's midpoint (a folded element made
  // straight) lies that far (the gap) from the surface point it stood for: the flat element
  // misses the surface by the gap at the edge and meets it at the opposite corner, so it is
  // tilted against the surface by about gap / width across that edge, a geometric error that
  // the kinks between elements need not show.
  if (!mesh.straightened_gap.empty()) {
    for (std::size_t t = 0; t < nt; ++t) {
      if (!share.computes(t)) continue;
      for (int k = 0; k < 3; ++k)
        tilt[t] = std::max(tilt[t], mesh.straightened_gap[static_cast<std::size_t>(mesh.edge_nodes[t][k])] / scale[t].across[k]);
    }
  }
  // Neumann edges: the flux misfit along the curved edge (the edges the solver takes as
  // Neumann: by the lift of the chord's midpoint).
  if (problem.is_neumann) {
    for (const auto& e : mesh.boundary_edges) {
      const Vec3 &pa = mesh.points[e.a], &pb = mesh.points[e.b];
      if (!problem.is_neumann(mesh.lift(0.5 * (pa + pb)))) continue;
      const auto t = static_cast<std::size_t>(e.triangle);
      if (!share.computes(t)) continue;
      int k = 0;
      while (k < 2 && mesh.triangles[t][k] != e.a) ++k;
      double integral = 0;
      for (const auto& [s, w] : kEdgeGauss) {
        const CurvedEdgePoint p = curved_edge_point(mesh, u, t, k, s);
        const double misfit = (problem.neumann_flux ? problem.neumann_flux(mesh.lift(p.x)) : 0.0) - p.flux;
        integral += w * p.speed * misfit * misfit;
      }
      eta2[t] += scale[t].across[k] * integral;
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    if (!share.computes(t)) continue;
    geometric[t] = std::max(delta[t] / scale[t].longest, tilt[t]) * std::sqrt(energy[t]);
    eta2[t] += geometric[t] * geometric[t];
  }
  return finish(std::move(eta2), std::move(geometric), share);
}

}  // namespace

Estimate residual_estimator(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u,
                            const WorkShare& share) {
  if (mesh.order == 2) return residual_estimator_quadratic(mesh, problem, u, share);
  require_order_1_or_2(mesh, "residual_estimator");
  const std::size_t nt = mesh.triangles.size();
  const auto& rule = triangle_quadrature();
  const std::vector<char> needed = needed_triangles(mesh, share, 2);
  const TriangleFields fields(mesh, u, needed);
  std::vector<double> h(nt), eta2(nt, 0.0), geometric(nt, 0.0), delta(nt, 0.0);
  const detail::SourceSamples source(mesh, problem, detail::SamplePoints::flat, share);
  for (std::size_t i = 0; i < nt; ++i) {
    if (!share.computes(i)) continue;
    const auto& t = mesh.triangles[i];
    h[i] = longest_edge(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
  }
  // Element residuals (and, with a projection, the distance to the surface), on every core.
  detail::for_each_index(nt, [&](std::size_t i) {
    if (!share.computes(i)) return;
    const auto& t = mesh.triangles[i];
    const Vec3 &p0 = mesh.points[t[0]], &p1 = mesh.points[t[1]], &p2 = mesh.points[t[2]];
    double r2 = 0;
    for (std::size_t n = 0; n < rule.size(); ++n) {
      const auto& q = rule[n];
      const Vec3 x = at(q.barycentric, p0, p1, p2);
      const Vec3 lifted = mesh.lift(x);
      const double uh = q.barycentric[0] * u[t[0]] + q.barycentric[1] * u[t[1]] + q.barycentric[2] * u[t[2]];
      const double r = source.at(i, n, lifted) - problem.c * uh;
      r2 += q.weight * fields.geo(i).area * r * r;
      if (mesh.projection) delta[i] = std::max(delta[i], distance(x, lifted));
    }
    eta2[i] += h[i] * h[i] * r2;
  });
  // Jumps of the conormal derivative across interior edges: each edge's term on every core,
  // added to its triangles in edge order.
  const std::vector<std::array<Side, 2>> edges = interior_edges(mesh, needed);
  add_interior_jumps(
      mesh, share, edges,
      [&](std::size_t n) -> std::array<double, 2> {  // ½ h_e ‖J‖²_e, sagitta
        const auto i = static_cast<std::size_t>(edges[n][1].triangle),
                   j = static_cast<std::size_t>(edges[n][0].triangle);
        const int k = edges[n][1].edge;
        const std::int32_t a = mesh.triangles[i][k], b = mesh.triangles[i][(k + 1) % 3];
        const Vec3 pa = mesh.points[a], pb = mesh.points[b];
        const double len = distance(pa, pb);
        // Outward conormals: the edge direction turned in each triangle's plane.
        const Vec3 dir = (pb - pa) * (1.0 / len);
        const Vec3 ni = cross(dir, fields.geo(i).normal), nj = cross(dir * -1.0, fields.geo(j).normal);
        const double jump = dot(fields.grad(i), ni) + dot(fields.grad(j), nj);
        // J is constant on e. The sagitta of an arc through the edge whose ends turn by the
        // normals' angle.
        // None on a crease: the surface is kinked there itself.
        const double theta = mesh.on_crease(i, k)
                                 ? 0.0
                                 : std::acos(std::clamp(dot(fields.geo(i).normal, fields.geo(j).normal), -1.0, 1.0));
        return {0.5 * len * len * jump * jump, len * theta / 8.0};
      },
      [](std::size_t, int) { return 1.0; }, eta2, delta);
  // Neumann edges: the flux misfit.
  if (problem.is_neumann) {
    for (const auto& e : mesh.boundary_edges) {
      const Vec3 pa = mesh.points[e.a], pb = mesh.points[e.b];
      const Vec3 mid = mesh.lift(0.5 * (pa + pb));
      if (!problem.is_neumann(mid)) continue;
      const auto i = static_cast<std::size_t>(e.triangle);
      if (!share.computes(i)) continue;
      const double len = distance(pa, pb);
      const Vec3 n = cross((pb - pa) * (1.0 / len), fields.geo(i).normal);
      const double misfit = (problem.neumann_flux ? problem.neumann_flux(mid) : 0.0) - dot(fields.grad(i), n);
      eta2[i] += len * len * misfit * misfit;
    }
  }
  for (std::size_t i = 0; i < nt; ++i) {
    if (!share.computes(i)) continue;
    geometric[i] = delta[i] / h[i] * std::sqrt(fields.geo(i).area) * norm(fields.grad(i));
    eta2[i] += geometric[i] * geometric[i];
  }
  return finish(std::move(eta2), std::move(geometric), share);
}

namespace {

// ZZ for P2: the gradient recovered at every node (corners and edge nodes) as the
// density-weighted mean of the elements' gradients there, interpolated quadratically, against
// ∇u_h on each curved element.
Estimate zz_estimator_quadratic(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const WorkShare& share) {
  const std::size_t nt = mesh.triangles.size();
  static constexpr std::array<std::array<double, 3>, 6> kNodes = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}}};
  const auto gradient_at = [&](const ElementPoint& p) { return evaluate(p, u).gradient; };
  std::vector<Vec3> recovered(mesh.num_dofs());
  std::vector<double> weight(mesh.num_dofs(), 0.0);
  // (On several processes, only the triangles around this process's nodes.)
  const std::vector<char> around = needed_triangles(mesh, share, 1);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!among(around, t)) continue;
    for (int k = 0; k < 6; ++k) {
      const ElementPoint p = element_point(mesh, t, kNodes[k]);
      recovered[p.dof[k]] += p.density * gradient_at(p);
      weight[p.dof[k]] += p.density;
    }
  }
  for (std::size_t v = 0; v < recovered.size(); ++v) {
    if (weight[v] > 0) recovered[v] *= 1.0 / weight[v];
  }
  std::vector<double> eta2(nt, 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!share.computes(t)) continue;
    for (const auto& q : triangle_quadrature()) {
      const ElementPoint p = element_point(mesh, t, q.barycentric);
      Vec3 g;
      for (int i = 0; i < p.nodes; ++i) g += p.value[i] * recovered[p.dof[i]];
      const Vec3 d = tangential(g, p.normal) - gradient_at(p);
      eta2[t] += q.weight * p.density * dot(d, d);
    }
  }
  return finish(std::move(eta2), std::vector<double>(nt, 0.0), share);
}

}  // namespace

Estimate zz_estimator(const SurfaceMesh& mesh, const Eigen::VectorXd& u, const WorkShare& share) {
  if (mesh.order == 2) return zz_estimator_quadratic(mesh, u, share);
  require_order_1_or_2(mesh, "zz_estimator");
  const std::size_t nt = mesh.triangles.size();
  std::vector<Vec3> recovered(mesh.num_dofs());
  std::vector<double> weight(mesh.num_dofs(), 0.0);
  const std::vector<char> around = needed_triangles(mesh, share, 1);  // (all on one process)
  const TriangleFields fields(mesh, u, around);
  for (std::size_t i = 0; i < nt; ++i) {
    if (!among(around, i)) continue;
    const auto& t = mesh.triangles[i];
    for (std::int32_t v : t) {
      recovered[v] += fields.geo(i).area * fields.grad(i);
      weight[v] += fields.geo(i).area;
    }
  }
  for (std::size_t v = 0; v < recovered.size(); ++v) {
    if (weight[v] > 0) recovered[v] *= 1.0 / weight[v];
  }
  const auto& rule = triangle_quadrature();
  std::vector<double> eta2(nt, 0.0);
  for (std::size_t i = 0; i < nt; ++i) {
    if (!share.computes(i)) continue;
    const auto& t = mesh.triangles[i];
    for (const auto& q : rule) {
      const Vec3 g = at(q.barycentric, recovered[t[0]], recovered[t[1]], recovered[t[2]]);
      const Vec3 d = tangential(g, fields.geo(i).normal) - fields.grad(i);
      eta2[i] += q.weight * fields.geo(i).area * dot(d, d);
    }
  }
  return finish(std::move(eta2), std::vector<double>(nt, 0.0), share);
}

Estimate ResidualEstimator::estimate(const SurfaceMesh& mesh, const Problem& problem,
                                     const Eigen::VectorXd& u, const WorkShare& share) const {
  return residual_estimator(mesh, problem, u, share);
}

Estimate ZzEstimator::estimate(const SurfaceMesh& mesh, const Problem&, const Eigen::VectorXd& u,
                               const WorkShare& share) const {
  return zz_estimator(mesh, u, share);
}

const std::vector<NamedEstimator>& estimator_table() {
  static const std::vector<NamedEstimator> table = {
      {"residual", "the residual estimator: element residuals, conormal jumps and the geometric term",
       [] { return std::shared_ptr<const ErrorEstimator>(std::make_shared<ResidualEstimator>()); }},
      {"zz", "Zienkiewicz-Zhu: the distance to the recovered (averaged) gradient",
       [] { return std::shared_ptr<const ErrorEstimator>(std::make_shared<ZzEstimator>()); }},
  };
  return table;
}

std::shared_ptr<const ErrorEstimator> make_estimator(const std::string& name) {
  return named_row(estimator_table(), name, "estimator").make();
}

}  // namespace rgbmesh::fem
