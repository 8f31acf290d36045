// How far a Loop-basis solution is from the exact one (see loop_elements.hpp): its errors
// where the exact solution is known, and the residual estimator that adaptivity marks by where
// it is not. Apart from the space and its solves (loop_elements.cpp) because nothing here is
// needed to compute a solution, as estimators.cpp is for P1 and P2; the geometry at points is
// shared through loop_points.hpp.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "for_each_index.hpp"
#include "loop_points.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem {

namespace {

using detail::dirichlet_at;
using detail::Frame;
using detail::frame_at;
using detail::laplacian_weights;
using detail::LaplacianWeights;
using detail::neumann_side;
using detail::point_source;
using detail::PointSource;
using detail::side_points;
using detail::SidePoint;

// Δ_Γ u_h at a quadrature point whose frame is known (the estimator and the error norms have
// it already; loop_laplacian computes it).
double laplacian_at(const LoopSpace& space, const LoopSpace::Element& e, Eigen::Index p, const Frame& f,
                    const Eigen::VectorXd& u) {
  const LoopQuadrature& r = *e.rule;
  const LaplacianWeights w = laplacian_weights(space, e, p, f);
  double sum = 0;
  for (std::size_t i = 0; i < e.dofs.size(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    sum += u(e.dofs[i]) *
           (w.a * r.duu(k, p) + w.b * r.duv(k, p) + w.c * r.dvv(k, p) + w.d * r.du(k, p) + w.e * r.dv(k, p));
  }
  return sum;
}

// Each element's residual h_T ‖f - c u_h + Δ_Γu_h‖_T, into out.eta.
void element_residuals(const LoopSpace& space, const Problem& problem, const Eigen::VectorXd& u,
                       Estimate& out) {
  const PointSource f = point_source(space, problem.source_values);
  detail::for_each_index(space.elements.size(), [&](std::size_t e) {
    const LoopSpace::Element& el = space.elements[e];
    const double* source = f.of(e);
    double residual = 0, area = 0;
    for (std::size_t p = 0; p < el.rule->size(); ++p) {
      const Frame fr = frame_at(space, el, static_cast<Eigen::Index>(p));
      double uh = 0;
      for (std::size_t i = 0; i < el.dofs.size(); ++i)
        uh += el.rule->value(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(p)) * u(el.dofs[i]);
      const double fp = source != nullptr ? source[p] : problem.source(fr.y);
      const double r = fp - problem.c * uh + laplacian_at(space, el, static_cast<Eigen::Index>(p), fr, u);
      const double w = el.rule->weight[p] * fr.density;
      residual += w * r * r;
      area += w;
    }
    const double h2 = 4 * area / std::sqrt(3.0);  // the squared side of the equilateral triangle of this area
    out.eta[e] = std::sqrt(h2 * residual);
  });
}

// On the boundary, what the weak conditions leave: h_E⁻¹ ‖g - u_h‖² on a Dirichlet side
// (Nitsche's solution does not interpolate g) and h_E ‖h - ∂ₘu_h‖² on a Neumann side.
void add_boundary_residuals(const LoopSpace& space, const Problem& problem, const Eigen::VectorXd& u,
                            Estimate& out) {
  std::vector<double> gauss_t, gauss_w;
  gauss_legendre(6, gauss_t, gauss_w);
  std::vector<std::vector<SidePoint>> points(space.boundary.size());
  std::vector<char> neumann(space.boundary.size(), 0);
  detail::for_each_index(space.boundary.size(),
                         [&](std::size_t k) { points[k] = side_points(space, space.boundary[k], gauss_t); });
  // The problem's own functions are called on one thread, as the solve calls them.
  for (std::size_t k = 0; k < points.size(); ++k)
    neumann[k] = neumann_side(space, space.boundary[k], problem) ? 1 : 0;
  std::vector<Vec3> at;
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!neumann[k])
      for (const SidePoint& p : points[k]) at.push_back(p.y);
  const std::vector<double> g = dirichlet_at(problem, at);
  std::size_t next = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const LoopSpace::Element& el = space.elements[space.boundary[k].element];
    double length = 0, squares = 0;
    for (std::size_t q = 0; q < points[k].size(); ++q) {
      const SidePoint& p = points[k][q];
      double uh = 0, dm = 0;
      for (std::size_t i = 0; i < el.dofs.size(); ++i) {
        uh += p.value(static_cast<Eigen::Index>(i)) * u(el.dofs[i]);
        dm += p.dm(static_cast<Eigen::Index>(i)) * u(el.dofs[i]);
      }
      const double r =
          neumann[k] ? (problem.neumann_flux ? problem.neumann_flux(p.y) : 0.0) - dm : g[next++] - uh;
      length += gauss_w[q] * p.speed;
      squares += gauss_w[q] * p.speed * r * r;
    }
    double& eta = out.eta[space.boundary[k].element];
    eta = std::sqrt(eta * eta + (neumann[k] ? length * squares : squares / length));
  }
}

// On the seams the functions are continuous but not smooth, and the weak form asks the two
// outward co-normal derivatives to cancel: ½ h_E ‖∂ₘu_h + ∂ₘ'u_h‖²_E to each element, as the
// P1 estimator's jumps.
void add_seam_jumps(const LoopSpace& space, const Eigen::VectorXd& u, Estimate& out) {
  std::vector<double> gauss_s, gauss_w;
  gauss_legendre(6, gauss_s, gauss_w);
  std::vector<std::array<double, 2>> jumps(space.seams.size());  // h_E ∫ jump², per seam
  detail::for_each_index(space.seams.size(), [&](std::size_t k) {
    const LoopSpace::Seam& seam = space.seams[k];
    std::array<std::vector<SidePoint>, 2> points;
    for (std::size_t i = 0; i < 2; ++i) {
      std::vector<double> t;
      for (const double x : gauss_s) t.push_back(seam.from[i] + x * (seam.to[i] - seam.from[i]));
      points[i] = side_points(space, {seam.element[i], seam.edge[i]}, t);
    }
    double length = 0, squares = 0;
    for (std::size_t q = 0; q < gauss_s.size(); ++q) {
      double jump = 0;
      for (std::size_t i = 0; i < 2; ++i) {
        const LoopSpace::Element& el = space.elements[seam.element[i]];
        for (std::size_t j = 0; j < el.dofs.size(); ++j)
          jump += points[i][q].dm(static_cast<Eigen::Index>(j)) * u(el.dofs[j]);
      }
      const double ds = gauss_w[q] * points[0][q].speed * std::abs(seam.to[0] - seam.from[0]);
      length += ds;
      squares += ds * jump * jump;
    }
    jumps[k] = {length, squares};
  });
  for (std::size_t k = 0; k < space.seams.size(); ++k)
    for (const std::size_t e : space.seams[k].element)
      out.eta[e] = std::sqrt(out.eta[e] * out.eta[e] + 0.5 * jumps[k][0] * jumps[k][1]);
}

}  // namespace

BiharmonicErrors loop_biharmonic_errors(const LoopSpace& space, const Eigen::VectorXd& u,
                                        const BiharmonicProblem& problem) {
  if (!problem.exact || !problem.exact_laplacian)
    throw InputError("problem '" + problem.name + "' has no exact solution");
  const ErrorNorms norms = loop_error_norms(space, u, *problem.exact);
  std::vector<double> squares(space.elements.size(), 0.0);
  detail::for_each_index(space.elements.size(), [&](std::size_t e) {
    const LoopSpace::Element& el = space.elements[e];
    for (std::size_t p = 0; p < el.rule->size(); ++p) {
      const Frame fr = frame_at(space, el, static_cast<Eigen::Index>(p));
      const double difference =
          problem.exact_laplacian(fr.y) - laplacian_at(space, el, static_cast<Eigen::Index>(p), fr, u);
      squares[e] += el.rule->weight[p] * fr.density * difference * difference;
    }
  });
  double sum = 0;
  for (const double x : squares) sum += x;
  return {norms.l2, norms.h1, std::sqrt(sum)};
}

ErrorNorms loop_error_norms(const LoopSpace& space, const Eigen::VectorXd& u, const ExactSolution& exact,
                            bool subtract_mean) {
  const std::size_t m = space.elements.size();
  std::vector<std::array<double, 4>> sums(m);  // ∫(u - u_h)², ∫|∇(u - u_h)|², ∫u, area
  detail::for_each_index(m, [&](std::size_t e) {
    const LoopSpace::Element& el = space.elements[e];
    std::array<double, 4> s{};
    for (std::size_t p = 0; p < el.rule->size(); ++p) {
      const auto pi = static_cast<Eigen::Index>(p);
      const Frame fr = frame_at(space, el, pi);
      // u_h and its parameter derivatives, then its surface gradient (without a gradient per
      // function, as loop_point gives).
      double uh = 0, uu = 0, uv = 0;
      for (std::size_t i = 0; i < el.dofs.size(); ++i) {
        const double ui = u(el.dofs[i]);
        const auto ii = static_cast<Eigen::Index>(i);
        uh += el.rule->value(ii, pi) * ui;
        uu += el.rule->du(ii, pi) * ui;
        uv += el.rule->dv(ii, pi) * ui;
      }
      const Vec3 grad_uh = fr.gradient(uu, uv);
      const double w = el.rule->weight[p] * fr.density;
      const double ue = exact.value(fr.y);
      const Vec3 grad_error = exact.surface_gradient(fr.y) - grad_uh;
      s[0] += w * (ue - uh) * (ue - uh);
      s[1] += w * dot(grad_error, grad_error);
      s[2] += w * (ue - uh);
      s[3] += w;
    }
    sums[e] = s;
  });
  std::array<double, 4> total{};
  for (const auto& s : sums)
    for (int k = 0; k < 4; ++k) total[static_cast<std::size_t>(k)] += s[static_cast<std::size_t>(k)];
  ErrorNorms out;
  // With the mean removed: ‖e - ē‖² = ‖e‖² - |Γ| ē².
  const double mean = subtract_mean ? total[2] / total[3] : 0.0;
  out.l2 = std::sqrt(std::max(0.0, total[0] - total[3] * mean * mean));
  out.h1 = std::sqrt(total[1]);
  return out;
}

double loop_laplacian(const LoopSpace& space, std::size_t element, std::size_t point,
                      const Eigen::VectorXd& u) {
  const LoopSpace::Element& e = space.elements[element];
  const Eigen::Index p = static_cast<Eigen::Index>(point);
  return laplacian_at(space, e, p, frame_at(space, e, p), u);
}

Estimate loop_residual_estimate(const LoopSpace& space, const Problem& problem, const Eigen::VectorXd& u) {
  Estimate out;
  out.eta.assign(space.elements.size(), 0.0);
  out.geometric.assign(space.elements.size(), 0.0);
  element_residuals(space, problem, u, out);
  if (!space.boundary.empty()) add_boundary_residuals(space, problem, u, out);
  if (!space.seams.empty()) add_seam_jumps(space, u, out);
  double sum = 0;
  for (const double x : out.eta) sum += x * x;
  out.total = std::sqrt(sum);
  return out;
}

}  // namespace rgbmesh::fem
