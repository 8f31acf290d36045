#include "rgbmesh/fem/estimators.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "parallel.hpp"

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

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Each triangle's geometry and the (constant) gradient of u_h on it.
struct TriangleFields {
  std::vector<TriangleGeometry> geo;
  std::vector<Vec3> grad;
};
TriangleFields triangle_fields(const SurfaceMesh& mesh, const Eigen::VectorXd& u) {
  TriangleFields f;
  f.geo.resize(mesh.triangles.size());
  f.grad.resize(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    f.geo[i] = triangle_geometry(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
    f.grad[i] = gradient(f.geo[i], t, u);
  }
  return f;
}

// The estimators are those of linear elements (issue 12: the quadratic ones are to come).
void require_linear(const SurfaceMesh& mesh, const char* what) {
  if (mesh.order != 1)
    throw std::invalid_argument(std::string(what) + ": only for linear elements (order 1) so far, not order " +
                                std::to_string(mesh.order));
}

Estimate finish(std::vector<double> eta_squared, std::vector<double> geometric) {
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
                       bool subtract_mean) {
  const auto& rule = triangle_quadrature();
  const std::size_t nt = mesh.triangles.size();
  double mean = 0;
  if (subtract_mean) {
    double integral = 0, area = 0;
    for (std::size_t t = 0; t < nt; ++t) {
      for (const auto& q : rule) {
        const ElementPoint p = element_point(mesh, t, q.barycentric);
        integral += q.weight * p.density * exact.value(mesh.lift(p.x));
        area += q.weight * p.density;
      }
    }
    mean = integral / area;
  }
  // Each triangle's share on every core, summed in triangle order (the numbers of one thread).
  std::vector<std::array<double, 2>> share(nt, {0.0, 0.0});
  detail::for_each_index(nt, [&](std::size_t t) {
    double& l2 = share[t][0];
    double& h1 = share[t][1];
    const auto& c = mesh.triangles[t];
    const double size = longest_edge(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]]);
    for (const auto& q : rule) {
      const ElementPoint p = element_point(mesh, t, q.barycentric);
      double uh = 0;
      Vec3 grad_h;
      for (int i = 0; i < p.nodes; ++i) {
        uh += p.value[i] * u[p.dof[i]];
        grad_h += u[p.dof[i]] * p.gradient[i];
      }
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
  double l2 = 0, h1 = 0;
  for (const auto& [a, b] : share) {
    l2 += a;
    h1 += b;
  }
  return {std::sqrt(l2), std::sqrt(h1)};
}

Estimate residual_estimator(const SurfaceMesh& mesh, const Problem& problem, const Eigen::VectorXd& u) {
  require_linear(mesh, "residual_estimator");
  const std::size_t nt = mesh.triangles.size();
  const auto& rule = triangle_quadrature();
  const auto [geo, grad] = triangle_fields(mesh, u);
  std::vector<double> h(nt), eta2(nt, 0.0), geometric(nt, 0.0), delta(nt, 0.0);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& t = mesh.triangles[i];
    h[i] = longest_edge(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
  }
  // Element residuals (and, with a projection, the distance to the surface), on every core.
  detail::for_each_index(nt, [&](std::size_t i) {
    const auto& t = mesh.triangles[i];
    const Vec3 &p0 = mesh.points[t[0]], &p1 = mesh.points[t[1]], &p2 = mesh.points[t[2]];
    double r2 = 0;
    for (const auto& q : rule) {
      const Vec3 x = at(q.barycentric, p0, p1, p2);
      const Vec3 lifted = mesh.lift(x);
      const double uh = q.barycentric[0] * u[t[0]] + q.barycentric[1] * u[t[1]] + q.barycentric[2] * u[t[2]];
      const double r = (problem.source ? problem.source(lifted) : 0.0) - problem.c * uh;
      r2 += q.weight * geo[i].area * r * r;
      if (mesh.projection) delta[i] = std::max(delta[i], distance(x, lifted));
    }
    eta2[i] += h[i] * h[i] * r2;
  });
  // Jumps of the conormal derivative across interior edges.
  std::unordered_map<std::uint64_t, std::pair<std::int32_t, int>> first;  // edge -> (triangle, local edge)
  first.reserve(nt * 2);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      const auto [it, inserted] = first.try_emplace(edge_key(a, b), static_cast<std::int32_t>(i), k);
      if (inserted) continue;
      const std::size_t j = static_cast<std::size_t>(it->second.first);
      const Vec3 pa = mesh.points[a], pb = mesh.points[b];
      const double len = distance(pa, pb);
      // Outward conormals: the edge direction turned in each triangle's plane.
      const Vec3 dir = (pb - pa) * (1.0 / len);
      const Vec3 ni = cross(dir, geo[i].normal), nj = cross(dir * -1.0, geo[j].normal);
      const double jump = dot(grad[i], ni) + dot(grad[j], nj);
      const double contribution = 0.5 * len * len * jump * jump;  // ½ h_e ‖J‖²_e, J constant on e
      eta2[i] += contribution;
      eta2[j] += contribution;
      if (!mesh.projection) {
        // The sagitta of an arc through the edge whose ends turn by the normals' angle.
        const double theta = std::acos(std::clamp(dot(geo[i].normal, geo[j].normal), -1.0, 1.0));
        const double sagitta = len * theta / 8.0;
        delta[i] = std::max(delta[i], sagitta);
        delta[j] = std::max(delta[j], sagitta);
      }
    }
  }
  // Neumann edges: the flux misfit.
  if (problem.is_neumann) {
    for (const auto& e : mesh.boundary_edges) {
      const Vec3 pa = mesh.points[e.a], pb = mesh.points[e.b];
      const Vec3 mid = mesh.lift(0.5 * (pa + pb));
      if (!problem.is_neumann(mid)) continue;
      const auto i = static_cast<std::size_t>(e.triangle);
      const double len = distance(pa, pb);
      const Vec3 n = cross((pb - pa) * (1.0 / len), geo[i].normal);
      const double misfit = (problem.neumann_flux ? problem.neumann_flux(mid) : 0.0) - dot(grad[i], n);
      eta2[i] += len * len * misfit * misfit;
    }
  }
  for (std::size_t i = 0; i < nt; ++i) {
    geometric[i] = delta[i] / h[i] * std::sqrt(geo[i].area) * norm(grad[i]);
    eta2[i] += geometric[i] * geometric[i];
  }
  return finish(std::move(eta2), std::move(geometric));
}

namespace {

// ZZ for P2: the gradient recovered at every node (corners and edge nodes) as the
// density-weighted mean of the elements' gradients there, interpolated quadratically, against
// ∇u_h on each curved element.
Estimate zz_estimator_quadratic(const SurfaceMesh& mesh, const Eigen::VectorXd& u) {
  const std::size_t nt = mesh.triangles.size();
  static constexpr std::array<std::array<double, 3>, 6> kNodes = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}}};
  const auto gradient_at = [&](const ElementPoint& p) {
    Vec3 g;
    for (int i = 0; i < p.nodes; ++i) g += u[p.dof[i]] * p.gradient[i];
    return g;
  };
  std::vector<Vec3> recovered(mesh.num_dofs());
  std::vector<double> weight(mesh.num_dofs(), 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
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
    for (const auto& q : triangle_quadrature()) {
      const ElementPoint p = element_point(mesh, t, q.barycentric);
      Vec3 g;
      for (int i = 0; i < p.nodes; ++i) g += p.value[i] * recovered[p.dof[i]];
      const Vec3 d = tangential(g, p.normal) - gradient_at(p);
      eta2[t] += q.weight * p.density * dot(d, d);
    }
  }
  return finish(std::move(eta2), std::vector<double>(nt, 0.0));
}

}  // namespace

Estimate zz_estimator(const SurfaceMesh& mesh, const Eigen::VectorXd& u) {
  if (mesh.order == 2) return zz_estimator_quadratic(mesh, u);
  require_linear(mesh, "zz_estimator");
  const std::size_t nt = mesh.triangles.size();
  std::vector<Vec3> recovered(mesh.num_dofs());
  std::vector<double> weight(mesh.num_dofs(), 0.0);
  const auto [geo, grad] = triangle_fields(mesh, u);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& t = mesh.triangles[i];
    for (std::int32_t v : t) {
      recovered[v] += geo[i].area * grad[i];
      weight[v] += geo[i].area;
    }
  }
  for (std::size_t v = 0; v < recovered.size(); ++v) {
    if (weight[v] > 0) recovered[v] *= 1.0 / weight[v];
  }
  const auto& rule = triangle_quadrature();
  std::vector<double> eta2(nt, 0.0);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& t = mesh.triangles[i];
    for (const auto& q : rule) {
      const Vec3 g = at(q.barycentric, recovered[t[0]], recovered[t[1]], recovered[t[2]]);
      const Vec3 d = tangential(g, geo[i].normal) - grad[i];
      eta2[i] += q.weight * geo[i].area * dot(d, d);
    }
  }
  return finish(std::move(eta2), std::vector<double>(nt, 0.0));
}

}  // namespace rgbmesh::fem
