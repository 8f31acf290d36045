// The clamped Kirchhoff plate with Loop-basis elements and Nitsche's boundary terms (see
// loop_plate.hpp).

#include "rgbmesh/fem/loop_plate.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "loop_assembly.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/timing.hpp"

namespace rgbmesh::fem {

namespace {

// The plane of a flat space: a point and two orthonormal directions in it. InputError when
// the control values leave the plane by more than 1e-9 of the mesh's extent.
struct Plane {
  Vec3 origin, e1, e2;
  Eigen::Vector2d to_plane(const Vec3& x) const { return {dot(x - origin, e1), dot(x - origin, e2)}; }
  Eigen::Vector2d along(const Vec3& d) const { return {dot(d, e1), dot(d, e2)}; }
};

Plane plane_of(const LoopSpace& space, const std::string& name) {
  Vec3 centre;
  for (const Vec3& x : space.control) centre += x;
  centre = (1.0 / static_cast<double>(space.control.size())) * centre;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double extent = 0;
  for (const Vec3& x : space.control) {
    const Eigen::Vector3d d(x.x - centre.x, x.y - centre.y, x.z - centre.z);
    scatter += d * d.transpose();
    extent = std::max(extent, d.norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  for (std::size_t i = 0; i < space.control.size(); ++i) {
    const Vec3& x = space.control[i];
    const double off = std::abs(normal.dot(Eigen::Vector3d(x.x - centre.x, x.y - centre.y, x.z - centre.z)));
    if (!(off <= 1e-9 * extent)) {
      char distance[64];
      std::snprintf(distance, sizeof distance, "%.3g (more than %.3g)", off, 1e-9 * extent);
      throw InputError("problem '" + name + "': a Kirchhoff plate needs a flat mesh, but vertex " +
                       std::to_string(space.vertex[i].idx) + " is " + distance +
                       " from the plane of the others (a curved surface is a shell)");
    }
  }
  const Eigen::Vector3d a = eigen.eigenvectors().col(2), b = eigen.eigenvectors().col(1);
  return {centre, {a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}};
}

// What the boundary terms need of each basis function at a point of a side, in the plane's
// coordinates: φ, ∂ₙφ, Δφ, ∂ₙΔφ; and the length element ds / dt.
struct SidePoint {
  Eigen::VectorXd value, dn, laplacian, dn_laplacian;
  double speed = 0, area_density = 0;
};

// Chain rule from the parameters (u, v) to the plane (x, y) = X(u, v) up to third order:
//   φ_a = G_i J_ia,  φ_ab = H_ij J_ia J_jb + G_i X_i,ab,
//   φ_abc = T_ijk J_ia J_jb J_kc + H_ij (X_i,ab J_jc + X_i,ac J_jb + X_i,bc J_ja) + G_i X_i,abc,
// solved for the gradient G, the Hessian H and the third derivatives T with K = J⁻¹.
// At the parameters (u, v), with the normal to the right of the direction (du, dv) (a side's).
SidePoint plate_point(const LoopSpace::Element& element, const std::vector<Eigen::Vector2d>& control,
                      const detail::SideParameters& side) {
  const LoopBasisAt at = evaluate_loop_basis(element.rule->patch, side.u, side.v);
  const Eigen::Index n = at.value.size();
  // The basis's parameter derivatives by multi-index: d1[a], d2[a][b], d3[a][b][c].
  const auto d1 = [&](int a) -> const Eigen::VectorXd& { return a == 0 ? at.du : at.dv; };
  const auto d2 = [&](int a, int b) -> const Eigen::VectorXd& {
    return a + b == 0 ? at.duu : (a + b == 1 ? at.duv : at.dvv);
  };
  const auto d3 = [&](int a, int b, int c) -> const Eigen::VectorXd& {
    const int vs = a + b + c;
    return vs == 0 ? at.duuu : (vs == 1 ? at.duuv : (vs == 2 ? at.duvv : at.dvvv));
  };
  // The map's derivatives: X_a, X_ab, X_abc (2-vectors).
  const auto map_sum = [&](const Eigen::VectorXd& w) {
    Eigen::Vector2d s = Eigen::Vector2d::Zero();
    for (Eigen::Index i = 0; i < n; ++i)
      s += w(i) * control[static_cast<std::size_t>(element.dofs[static_cast<std::size_t>(i)])];
    return s;
  };
  Eigen::Matrix2d jacobian;  // J_ia = ∂X_i / ∂ξ_a
  for (int a = 0; a < 2; ++a) jacobian.col(a) = map_sum(d1(a));
  std::array<std::array<Eigen::Vector2d, 2>, 2> x2;
  std::array<std::array<std::array<Eigen::Vector2d, 2>, 2>, 2> x3;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      x2[a][b] = map_sum(d2(a, b));
      for (int c = 0; c < 2; ++c) x3[a][b][c] = map_sum(d3(a, b, c));
    }
  const Eigen::Matrix2d k = jacobian.inverse();  // K_ai
  const Eigen::Vector2d tangent = jacobian * Eigen::Vector2d(side.du, side.dv);
  SidePoint out;
  out.speed = tangent.norm();
  // Outward: to the right of a counter-clockwise walk (parameter triangle's orientation in the
  // plane given by det J).
  Eigen::Vector2d normal(tangent.y(), -tangent.x());
  normal *= (jacobian.determinant() > 0 ? 1.0 : -1.0) / out.speed;
  out.value = at.value;
  out.area_density = std::abs(jacobian.determinant());
  out.dn.resize(n), out.laplacian.resize(n), out.dn_laplacian.resize(n);
  for (Eigen::Index f = 0; f < n; ++f) {
    Eigen::Vector2d g1(at.du(f), at.dv(f));
    const Eigen::Vector2d grad = k.transpose() * g1;  // G = J⁻ᵀ (φ_u, φ_v)
    Eigen::Matrix2d r2;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) r2(a, b) = d2(a, b)(f) - grad.dot(x2[a][b]);
    const Eigen::Matrix2d hessian = k.transpose() * r2 * k;
    // R_abc = φ_abc − H-terms − G-terms, then T_ijk = R_abc K_ai K_bj K_ck.
    double r3[2][2][2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const Eigen::Vector2d ja = jacobian.col(a), jb = jacobian.col(b), jc = jacobian.col(c);
          r3[a][b][c] = d3(a, b, c)(f) - x2[a][b].dot(hessian * jc) - x2[a][c].dot(hessian * jb) -
                        x2[b][c].dot(hessian * ja) - grad.dot(x3[a][b][c]);
        }
    // ∂ₙΔφ = n_k Σ_i T_iik.
    double dn_lap = 0;
    for (int i = 0; i < 2; ++i)
      for (int kk = 0; kk < 2; ++kk) {
        double tiik = 0;
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c) tiik += r3[a][b][c] * k(a, i) * k(b, i) * k(c, kk);
        dn_lap += normal(kk) * tiik;
      }
    out.dn(f) = grad.dot(normal);
    out.laplacian(f) = hessian.trace();
    out.dn_laplacian(f) = dn_lap;
  }
  return out;
}

}  // namespace

PlateProblem clamped_square_plate() {
  PlateProblem p;
  p.name = "clamped-square-plate";
  p.rigidity = 1;
  p.load = [](const Vec3&) { return 1.0; };
  return p;
}

Solution solve_clamped_plate(const LoopSpace& space, const PlateProblem& problem, const PlateOptions& options,
                             const SolveOptions& solve) {
  if (!problem.load) throw InputError("problem '" + problem.name + "' has no load");
  if (!(problem.rigidity > 0) || !std::isfinite(problem.rigidity))
    throw InputError("problem '" + problem.name + "': the rigidity D must be finite and > 0");
  if (space.projection)
    throw InputError("problem '" + problem.name + "': a Kirchhoff plate lies in its plane (no projection)");
  if (space.boundary.empty())
    throw InputError("problem '" + problem.name +
                     "': the plate's space has no boundary to clamp (build it with LoopBoundary::ghost_ring "
                     "on a mesh with a ring of ghost triangles)");
  for (const LoopSpace::Element& element : space.elements)
    if (element.rule->extension)
      throw InputError("problem '" + problem.name +
                       "': the plate is clamped on a ghost ring (LoopBoundary::ghost_ring), not on a "
                       "completed boundary");
  detail::require_smooth(space, problem.name);
  detail::check_nitsche_options(problem.name, options.penalty, 2, "PlateOptions::penalty, 3 by default",
                                options.edge_points);
  const Plane plane = plane_of(space, problem.name);
  const double d = problem.rigidity;
  const ScalarField& load = problem.load;
  detail::LoopSystem s = detail::assemble_loop_system(
      space, true, 0.0, [&load, d](const Vec3& x) { return load(x) / d; }, PointValues(), problem.name);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Eigen::Vector2d> control;
  control.reserve(space.control.size());
  for (const Vec3& x : space.control) control.push_back(plane.to_plane(x));
  std::vector<double> gauss_t, gauss_w;
  gauss_legendre(options.edge_points, gauss_t, gauss_w);
  // The sides of each element, which share its penalty.
  std::map<std::size_t, std::vector<int>> sides_of;
  for (const LoopSpace::Side& side : space.boundary) sides_of[side.element].push_back(side.edge);
  for (const auto& [e, edges] : sides_of) {
    const LoopSpace::Element& element = space.elements[e];
    // At an extraordinary vertex the basis's third derivatives are unbounded, and Nitsche's
    // ∂ₙΔw term with them: a boundary through one converges poorly (measured: -15% at 32
    // cells a side on alternating diagonals), so it is refused.
    for (const int edge : edges)
      for (const int corner : {edge, (edge + 1) % 3})
        if (element.rule->patch.valence[static_cast<std::size_t>(corner)] != 6)
          throw InputError(
              "problem '" + problem.name + "': the plate's boundary passes through vertex " +
              std::to_string(
                  space.vertex[static_cast<std::size_t>(element.dofs[static_cast<std::size_t>(corner)])]
                      .idx) +
              " of valence " + std::to_string(element.rule->patch.valence[static_cast<std::size_t>(corner)]) +
              "; clamping it weakly needs third derivatives, unbounded at such a vertex. Give "
              "the boundary vertices valence 6 (a regular row along each side, the ghost ring "
              "beyond it)");
    const Eigen::Index n = static_cast<Eigen::Index>(element.dofs.size());
    // The element's energy ∫_T (Δφ_i)(Δφ_j), and what its sides' terms can take of it.
    Eigen::MatrixXd energy = Eigen::MatrixXd::Zero(n, n), on_sides = energy, third = energy;
    const LoopQuadrature& rule = *element.rule;
    for (std::size_t p = 0; p < rule.size(); ++p) {
      const SidePoint at = plate_point(element, control, {rule.u[p], rule.v[p], 1, 0});
      energy.noalias() += (rule.weight[p] * at.area_density) * (at.laplacian * at.laplacian.transpose());
    }
    std::vector<std::vector<SidePoint>> points(edges.size());
    std::vector<double> length(edges.size(), 0.0);
    for (std::size_t k = 0; k < edges.size(); ++k) {
      for (std::size_t q = 0; q < gauss_t.size(); ++q) {
        points[k].push_back(plate_point(element, control, detail::side_parameters(edges[k], gauss_t[q])));
        length[k] += gauss_w[q] * points[k].back().speed;
      }
      for (std::size_t q = 0; q < gauss_t.size(); ++q) {
        const SidePoint& p = points[k][q];
        const double w = gauss_w[q] * p.speed, h = length[k];
        on_sides.noalias() += (w * h) * (p.laplacian * p.laplacian.transpose());
        third.noalias() += (w * h * h * h) * (p.dn_laplacian * p.dn_laplacian.transpose());
      }
    }
    // Coercive when γ₁ > 2 C₁ and γ₃ > 2 C₃ (Young's inequality: each symmetric term then takes
    // less than half of the element's energy).
    const double c1 = detail::largest_ratio(energy, on_sides), c3 = detail::largest_ratio(energy, third);

    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(n, n);
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const double h = length[k];
      const double beta1 = options.penalty * c1 / h, beta3 = options.penalty * c3 / (h * h * h);
      for (std::size_t q = 0; q < points[k].size(); ++q) {
        const SidePoint& p = points[k][q];
        const double w = gauss_w[q] * p.speed;
        local.noalias() -= w * (p.laplacian * p.dn.transpose() + p.dn * p.laplacian.transpose());
        local.noalias() += w * (p.dn_laplacian * p.value.transpose() + p.value * p.dn_laplacian.transpose());
        local.noalias() += (w * beta1) * (p.dn * p.dn.transpose());
        local.noalias() += (w * beta3) * (p.value * p.value.transpose());
      }
    }
    detail::add_local(s.a, element.dofs, local);
  }
  s.seconds += seconds_since(t0);
  return detail::solve_nitsche_system(s, solve, problem.name, options.penalty,
                                      "PlateOptions::penalty, 3 by default");
}

}  // namespace rgbmesh::fem
