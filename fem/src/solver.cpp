#include "rgbmesh/fem/solver.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "amg.hpp"
#include "for_each_index.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/timing.hpp"
#include "source_samples.hpp"

#if defined(RGBMESH_HAVE_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif

namespace rgbmesh::fem {

namespace {

using Triplet = Eigen::Triplet<double>;

Vec3 at(const std::array<double, 3>& l, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return l[0] * p0 + l[1] * p1 + l[2] * p2;
}

// Dirichlet DOFs: the ends of every boundary edge that is not Neumann.
std::vector<char> dirichlet_dofs(const SurfaceMesh& mesh, const Problem& problem) {
  std::vector<char> dir(mesh.num_dofs(), 0);
  for (const auto& e : mesh.boundary_edges) {
    const Vec3 mid = mesh.lift(0.5 * (mesh.points[e.a] + mesh.points[e.b]));
    if (problem.is_neumann && problem.is_neumann(mid)) continue;
    dir[e.a] = dir[e.b] = 1;
    if (e.middle >= 0) dir[e.middle] = 1;
  }
  return dir;
}

template <class Solver>
Eigen::VectorXd factor_and_solve(Solver& solver, const SparseMatrix& a, const Eigen::VectorXd& rhs,
                                 const char* name) {
  solver.compute(a);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error(std::string(name) + ": the factorization failed: the system is singular or not positive definite");
  Eigen::VectorXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success) throw std::runtime_error(std::string(name) + ": the solve failed");
  return x;
}

// Calls fn(edge, weight, values, h) at the quadrature points of every Neumann edge, with the
// basis functions of the edge's nodes (e.a, e.b, e.middle) there and the flux h. P1: the
// straight edge, two-point Gauss (exact for cubics along it); P2: the quadratic curve through
// the three nodes, three-point Gauss, the weight carrying the curve's length element.
template <class Fn>
void for_each_neumann_point(const SurfaceMesh& mesh, const Problem& problem, Fn&& fn) {
  if (!problem.neumann_flux || !problem.is_neumann) return;
  const double r = 0.5 / std::sqrt(3.0), r3 = 0.5 * std::sqrt(0.6);
  for (const auto& e : mesh.boundary_edges) {
    const Vec3 &pa = mesh.points[e.a], &pb = mesh.points[e.b];
    if (!problem.is_neumann(mesh.lift(0.5 * (pa + pb)))) continue;
    if (e.middle < 0) {
      const double len = distance(pa, pb);
      for (double s : {0.5 - r, 0.5 + r})
        fn(e, 0.5 * len, std::array<double, 3>{1 - s, s, 0.0}, problem.neumann_flux(mesh.lift((1 - s) * pa + s * pb)));
      continue;
    }
    const Vec3& pm = mesh.points[e.middle];
    for (const auto& [s, w] : {std::pair{0.5 - r3, 5.0 / 18}, std::pair{0.5, 8.0 / 18}, std::pair{0.5 + r3, 5.0 / 18}}) {
      const std::array<double, 3> v = {(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)};
      const Vec3 x = v[0] * pa + v[1] * pb + v[2] * pm;
      const Vec3 dx = (4 * s - 3) * pa + (4 * s - 1) * pb + (4 - 8 * s) * pm;
      fn(e, w * norm(dx), v, problem.neumann_flux(mesh.lift(x)));
    }
  }
}

// The stiffness and mass matrices of triangle t, and the integrals of its basis functions.
// P1: the exact formulas of a flat triangle; P2: the degree-5 rule on the curved element.
struct LocalSystem {
  int nodes = 3;
  std::array<std::int32_t, 6> dof{};
  double stiffness[6][6] = {}, mass[6][6] = {};
  std::array<double, 6> integral{};
};
void local_system(const SurfaceMesh& mesh, std::size_t t, LocalSystem& out) {
  const auto& c = mesh.triangles[t];
  if (mesh.order == 1) {
    const TriangleGeometry g = triangle_geometry(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]]);
    out.nodes = 3;
    for (int i = 0; i < 3; ++i) {
      out.dof[i] = c[i];
      out.integral[i] = g.area / 3.0;
      for (int j = 0; j < 3; ++j) {
        out.stiffness[i][j] = g.area * dot(g.grad[i], g.grad[j]);
        out.mass[i][j] = g.area / 12.0 * (i == j ? 2.0 : 1.0);
      }
    }
    return;
  }
  out = LocalSystem{};
  for (const auto& q : triangle_quadrature()) {
    const ElementPoint p = element_point(mesh, t, q.barycentric);
    const double w = q.weight * p.density;
    out.nodes = p.nodes;
    out.dof = p.dof;
    for (int i = 0; i < p.nodes; ++i) {
      out.integral[i] += w * p.value[i];
      for (int j = 0; j < p.nodes; ++j) {
        out.stiffness[i][j] += w * dot(p.gradient[i], p.gradient[j]);
        out.mass[i][j] += w * p.value[i] * p.value[j];
      }
    }
  }
}

// ∫f + ∫h over the surface and ∫|f| + ∫|h|, for the compatibility check: the degree-5 rule on
// each triangle with the lifted area element (Neumann edges as in the load vector).
std::pair<double, double> surface_integral_of_data(const SurfaceMesh& mesh, const Problem& problem,
                                                   const WorkShare& share) {
  double total = 0, scale = 0;
  const auto& rule = triangle_quadrature();
  const detail::SourceSamples source(mesh, problem, detail::SamplePoints::flat, share);
  if (source.any()) {
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      if (!share.computes(k)) continue;
      const auto& t = mesh.triangles[k];
      const Vec3 &p0 = mesh.points[t[0]], &p1 = mesh.points[t[1]], &p2 = mesh.points[t[2]];
      const TriangleGeometry g = triangle_geometry(p0, p1, p2);
      const double size = std::sqrt(g.area);
      for (std::size_t n = 0; n < rule.size(); ++n) {
        const auto& q = rule[n];
        const Vec3 x = at(q.barycentric, p0, p1, p2);
        const double w = q.weight * g.area * mesh.lift_area_factor(x, g.normal, size);
        const double f = source.at(k, n, mesh.lift(x));
        total += w * f;
        scale += w * std::abs(f);
      }
    }
  }
  for_each_neumann_point(mesh, problem, [&](const SurfaceMesh::BoundaryEdge& e, double weight, const std::array<double, 3>&, double h) {
    if (!share.computes(static_cast<std::size_t>(e.triangle))) return;
    total += weight * h;
    scale += weight * std::abs(h);
  });
  double both[2] = {total, scale};
  if (share.sum) share.sum(both, 2);
  return {both[0], both[1]};
}

}  // namespace

const char* to_string(SolverKind k) {
  switch (k) {
    case SolverKind::automatic: return "auto";
    case SolverKind::ldlt: return "ldlt";
    case SolverKind::cg_ichol: return "cg";
    case SolverKind::cholmod: return "cholmod";
    case SolverKind::amg: return "amg";
  }
  return "?";
}

SolverKind parse_solver(const std::string& name) {
  if (name == "auto") return SolverKind::automatic;
  if (name == "ldlt") return SolverKind::ldlt;
  if (name == "cg") return SolverKind::cg_ichol;
  if (name == "cholmod") return SolverKind::cholmod;
  if (name == "amg") return SolverKind::amg;
  throw InputError("unknown solver '" + name + "' (auto, ldlt, cg, cholmod, amg)");
}

const std::vector<std::array<const char*, 2>>& amg_options() {
  static const std::vector<std::array<const char*, 2>> options = {
      {"-rgbmesh_amg_pc_hypre_boomeramg_coarsen_type", "HMIS"},
      {"-rgbmesh_amg_pc_hypre_boomeramg_interp_type", "ext+i"},
      {"-rgbmesh_amg_pc_hypre_boomeramg_P_max", "4"},
      {"-rgbmesh_amg_pc_hypre_boomeramg_strong_threshold", "0.25"},
      // Aggressive coarsening on the first level: a coarse grid about a fourth as large, so the
      // setup and each V-cycle cost less, for more iterations. Measured 2026-12-07 (adaptive
      // sphere-peak, the solve alone): Loop THB at 52,954 unknowns 0.95 s in 32 iterations,
      // 0.39 s in 30 with it; P2 at 198,722 0.97 s in 6 (warm start), 0.74 s in 15; P1 at
      // 154,566 0.69 s, 0.49 s.
      {"-rgbmesh_amg_pc_hypre_boomeramg_agg_nl", "1"},
  };
  return options;
}

bool cholmod_available() {
#if defined(RGBMESH_HAVE_CHOLMOD)
  return true;
#else
  return false;
#endif
}

bool amg_available() { return detail::amg_available(); }

namespace {

// The load vector of this process's triangles (and Neumann edges).
Eigen::VectorXd shared_load_vector(const SurfaceMesh& mesh, const Problem& problem, const WorkShare& share) {
  Eigen::VectorXd load = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.num_dofs()));
  const auto& rule = triangle_quadrature();
  const detail::SourceSamples source(mesh, problem, detail::SamplePoints::element, share);
  if (source.any()) {
    // Each triangle's ∫ f φ_i on every core, then added up in triangle order (as one thread
    // would: the same numbers whatever the number of threads).
    const std::size_t nt = mesh.triangles.size();
    const int nodes = mesh.order == 2 ? 6 : 3;
    std::vector<std::array<double, 6>> local(nt);
    detail::for_each_index(nt, [&](std::size_t t) {
      std::array<double, 6>& l = local[t];
      l.fill(0.0);
      if (!share.computes(t)) return;
      if (mesh.order == 1) {
        const auto& c = mesh.triangles[t];
        const Vec3 &p0 = mesh.points[c[0]], &p1 = mesh.points[c[1]], &p2 = mesh.points[c[2]];
        const double area = triangle_geometry(p0, p1, p2).area;
        for (std::size_t n = 0; n < rule.size(); ++n) {
          const auto& q = rule[n];
          const double f = source.at(t, n, mesh.lift(at(q.barycentric, p0, p1, p2)));
          for (int i = 0; i < 3; ++i) l[i] += q.weight * area * f * q.barycentric[i];
        }
      } else {
        for (std::size_t n = 0; n < rule.size(); ++n) {
          const auto& q = rule[n];
          const ElementPoint p = element_point(mesh, t, q.barycentric);
          const double wf = q.weight * p.density * source.at(t, n, mesh.lift(p.x));
          for (int i = 0; i < p.nodes; ++i) l[i] += wf * p.value[i];
        }
      }
    });
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& c = mesh.triangles[t];
      for (int i = 0; i < nodes; ++i) load[i < 3 ? c[i] : mesh.edge_nodes[t][i - 3]] += local[t][i];
    }
  }
  for_each_neumann_point(mesh, problem, [&](const SurfaceMesh::BoundaryEdge& e, double weight, const std::array<double, 3>& v, double h) {
    if (!share.computes(static_cast<std::size_t>(e.triangle))) return;
    load[e.a] += weight * h * v[0];
    load[e.b] += weight * h * v[1];
    if (e.middle >= 0) load[e.middle] += weight * h * v[2];
  });
  return load;
}

// Every process's rows of a shared system: each DOF's row belongs to the lowest part among its
// triangles (the same on every process).
std::vector<std::int32_t> row_parts(const SurfaceMesh& mesh, const std::vector<std::int32_t>& part,
                                    const std::vector<Eigen::Index>& index, Eigen::Index free_dofs) {
  std::vector<std::int32_t> owner(mesh.num_dofs(), std::numeric_limits<std::int32_t>::max());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& c = mesh.triangles[t];
    for (int i = 0; i < 3; ++i) owner[c[i]] = std::min(owner[c[i]], part[t]);
    if (mesh.order == 2)
      for (const std::int32_t e : mesh.edge_nodes[t]) owner[e] = std::min(owner[e], part[t]);
  }
  std::vector<std::int32_t> rows(static_cast<std::size_t>(free_dofs));
  for (std::size_t i = 0; i < owner.size(); ++i)
    if (index[i] >= 0) rows[static_cast<std::size_t>(index[i])] = owner[i];
  return rows;
}

}  // namespace

Eigen::VectorXd load_vector(const SurfaceMesh& mesh, const Problem& problem) {
  return shared_load_vector(mesh, problem, WorkShare{});
}

System assemble(const SurfaceMesh& mesh, const Problem& problem) {
  const auto n = static_cast<Eigen::Index>(mesh.num_dofs());
  std::vector<Triplet> k, m;
  k.reserve(mesh.triangles.size() * 9);
  m.reserve(mesh.triangles.size() * 9);
  LocalSystem local;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    local_system(mesh, t, local);
    for (int i = 0; i < local.nodes; ++i) {
      for (int j = 0; j < local.nodes; ++j) {
        k.emplace_back(local.dof[i], local.dof[j], local.stiffness[i][j]);
        m.emplace_back(local.dof[i], local.dof[j], local.mass[i][j]);
      }
    }
  }
  System s;
  s.stiffness.resize(n, n);
  s.mass.resize(n, n);
  s.stiffness.setFromTriplets(k.begin(), k.end());
  s.mass.setFromTriplets(m.begin(), m.end());
  s.load = load_vector(mesh, problem);
  return s;
}

namespace {

// The system K + cM on the free DOFs (index: each DOF's free row, or -1 where its value is
// fixed), from the triangles this process computes, with the fixed values moved to the
// right-hand side and the vertex areas ∫φi summed in the same pass.
// Straight into compressed columns, without a triplet list: first the pattern (the free DOFs
// that share a computed triangle, gathered per DOF through its triangles), then the element
// matrices, a block of triangles at a time on every core, added in triangle order. Each entry
// is then the sum setFromTriplets forms from the element entries, in the same order, bit for
// bit, and the same for any number of threads; but the memory is the matrix's, not a 16-byte
// triplet per element entry plus the transposed copy setFromTriplets makes (on 1.9 million P1
// triangles the triplets alone were 270 MB, and the assembly was the peak of a solve).
SparseMatrix assemble(const SurfaceMesh& mesh, const Problem& problem, const WorkShare& share,
                      const std::vector<Eigen::Index>& index, Eigen::Index nf, const Eigen::VectorXd& u,
                      Eigen::VectorXd& rhs, Eigen::VectorXd& area) {
  const std::size_t n = index.size();
  const int nodes = mesh.order == 2 ? 6 : 3;
  const auto node = [&mesh](std::size_t t, int i) {
    return static_cast<std::size_t>(i < 3 ? mesh.triangles[t][i] : mesh.edge_nodes[t][i - 3]);
  };
  std::vector<std::size_t> mine;  // (on several processes, only this process's triangles)
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (share.computes(t)) mine.push_back(t);
  // The pattern. Each free DOF's computed triangles (as compressed lists), then its column's
  // rows: counted, then written, sorted, on every core.
  std::vector<std::size_t> dof_of_free(static_cast<std::size_t>(nf));
  for (std::size_t d = 0; d < n; ++d)
    if (index[d] >= 0) dof_of_free[static_cast<std::size_t>(index[d])] = d;
  std::vector<std::size_t> first_around(n + 1, 0);
  for (const std::size_t t : mine)
    for (int i = 0; i < nodes; ++i) ++first_around[node(t, i) + 1];
  for (std::size_t d = 0; d < n; ++d) first_around[d + 1] += first_around[d];
  std::vector<std::int32_t> around(first_around[n]);  // (the FE mesh numbers its triangles in int32)
  {
    std::vector<std::size_t> next(first_around.begin(), first_around.end() - 1);
    for (const std::size_t t : mine)
      for (int i = 0; i < nodes; ++i) around[next[node(t, i)]++] = static_cast<std::int32_t>(t);
  }
  SparseMatrix a(nf, nf);
  const auto column_rows = [&](Eigen::Index j, std::vector<Eigen::Index>& rows) {
    rows.clear();
    const std::size_t d = dof_of_free[static_cast<std::size_t>(j)];
    for (std::size_t k = first_around[d]; k < first_around[d + 1]; ++k)
      for (int i = 0; i < nodes; ++i)
        if (const Eigen::Index r = index[node(static_cast<std::size_t>(around[k]), i)]; r >= 0)
          rows.push_back(r);
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  };
  int* const outer = a.outerIndexPtr();
  outer[0] = 0;
  detail::for_each_index(static_cast<std::size_t>(nf), [&](std::size_t j) {
    thread_local std::vector<Eigen::Index> rows;
    column_rows(static_cast<Eigen::Index>(j), rows);
    outer[j + 1] = static_cast<int>(rows.size());
  });
  for (Eigen::Index j = 0; j < nf; ++j) {
    if (outer[j + 1] > std::numeric_limits<int>::max() - outer[j])
      throw std::bad_alloc();  // (Eigen's int indices)
    outer[j + 1] += outer[j];
  }
  a.resizeNonZeros(outer[nf]);
  int* const inner = a.innerIndexPtr();
  double* const value = a.valuePtr();
  detail::for_each_index(static_cast<std::size_t>(nf), [&](std::size_t j) {
    thread_local std::vector<Eigen::Index> rows;
    column_rows(static_cast<Eigen::Index>(j), rows);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      inner[static_cast<std::size_t>(outer[j]) + k] = static_cast<int>(rows[k]);
      value[static_cast<std::size_t>(outer[j]) + k] = 0.0;
    }
  });
  std::vector<std::int32_t>().swap(around);
  std::vector<std::size_t>().swap(first_around);
  std::vector<std::size_t>().swap(dof_of_free);
  // The values: element matrices on every core, a block at a time, then added in order.
  constexpr std::size_t kBlock = 1 << 14;
  std::vector<LocalSystem> block(std::min(kBlock, mine.size()));
  for (std::size_t begin = 0; begin < mine.size(); begin += kBlock) {
    const std::size_t count = std::min(kBlock, mine.size() - begin);
    detail::for_each_index(count, [&](std::size_t k) { local_system(mesh, mine[begin + k], block[k]); });
    for (std::size_t k = 0; k < count; ++k) {
      const LocalSystem& local = block[k];
      for (int i = 0; i < local.nodes; ++i) {
        area[local.dof[i]] += local.integral[i];
        const Eigen::Index ri = index[local.dof[i]];
        if (ri < 0) continue;
        for (int j = 0; j < local.nodes; ++j) {
          const double entry = local.stiffness[i][j] + problem.c * local.mass[i][j];
          const Eigen::Index cj = index[local.dof[j]];
          if (cj < 0) {
            rhs[ri] -= entry * u[local.dof[j]];
          } else {
            int* const rows_end = inner + outer[cj + 1];
            value[std::lower_bound(inner + outer[cj], rows_end, static_cast<int>(ri)) - inner] += entry;
          }
        }
      }
    }
  }
  return a;
}

}  // namespace

namespace {

// A sum over the processes of a shared solve (the value itself on one process).
double total_over(const WorkShare& share, double value) {
  if (share.sum) share.sum(&value, 1);
  return value;
}

// What a solve holds fixed: the Dirichlet DOFs with their data and, for a problem without
// Dirichlet boundary and c = 0, one DOF and the zero-mean condition.
struct Constraints {
  std::vector<char> fixed;  // per DOF
  Eigen::VectorXd u;        // the fixed DOFs' values, 0 elsewhere
  bool zero_mean = false;
  double mean_load = 0;  // ∫f + ∫h, removed in the zero-mean case
};

Constraints constrain(const SurfaceMesh& mesh, const Problem& problem, const WorkShare& share, bool shared,
                      const Eigen::VectorXd& b) {
  const auto n = static_cast<Eigen::Index>(mesh.num_dofs());
  Constraints c;
  c.fixed = dirichlet_dofs(mesh, problem);
  c.u = Eigen::VectorXd::Zero(n);
  if (problem.dirichlet && problem.dirichlet_values)
    throw InputError("problem '" + problem.name + "': both dirichlet and dirichlet_values are set (give one)");
  std::vector<Eigen::Index> fixed_dofs;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (c.fixed[i]) fixed_dofs.push_back(i);
  }
  bool any_dirichlet = !fixed_dofs.empty();
  if (problem.dirichlet) {
    for (const Eigen::Index i : fixed_dofs) c.u[i] = problem.dirichlet(mesh.lift(mesh.points[i]));
  } else if (problem.dirichlet_values && !fixed_dofs.empty()) {
    std::vector<Vec3> at_dofs;
    at_dofs.reserve(fixed_dofs.size());
    for (const Eigen::Index i : fixed_dofs) at_dofs.push_back(mesh.lift(mesh.points[i]));
    const std::vector<double> g = detail::point_values(problem.dirichlet_values, at_dofs);
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k) c.u[fixed_dofs[k]] = g[k];
  }
  if (total_over(share, c.u.allFinite() ? 0.0 : 1.0) > 0)  // (decided together, as the load's check)
    throw InputError("problem '" + problem.name + "': the Dirichlet data are not finite somewhere on the boundary");
  // (Decided together: on a distributed mesh each process sees the boundary of its own view.)
  if (shared) any_dirichlet = total_over(share, any_dirichlet ? 1.0 : 0.0) > 0;
  if (!any_dirichlet && problem.c == 0) {
    // Closed surface (or all Neumann) with c = 0: solutions differ by constants, and exist
    // only if ∫f + ∫h = 0. Check it, make it exact for the discrete system (once the vertex
    // areas are known), fix one value and shift the result to zero mean.
    // The discrete load need not sum to zero even when the source has zero mean: the flat
    // triangles' areas differ from the surface's by O(h²), unevenly on an adaptive mesh. So
    // the check integrates the source over the surface itself (the lifted area element when
    // a projection is known), and only a source whose mean is clearly non-zero is refused;
    // the discrete load is then made compatible by removing its mean, as FEM codes do.
    c.zero_mean = true;
    const auto [total, scale] = surface_integral_of_data(mesh, problem, share);
    if (std::abs(total) > problem.mean_tolerance * scale)
      throw InputError("problem '" + problem.name +
                       "': on a closed surface with c = 0 the source must have zero mean, but ∫f = " +
                       std::to_string(total) + " (relative " +
                       std::to_string(scale > 0 ? total / scale : 0.0) +
                       "); use c > 0, or subtract the mean");
    c.mean_load = total_over(share, b.sum());
    c.fixed[0] = 1;
  }
  return c;
}

// The solution of the free system and how it was found.
struct FreeSolution {
  Eigen::VectorXd x;
  SolverKind kind = SolverKind::automatic;  // the solver that ran
  int iterations = 0;
  double shared_residual = -1;  // a shared system's residual, as its solver measured it
};

// Solves a x = rhs by options' choice. Automatic: sparse LDLT for small systems; from 20,000
// unknowns CG with algebraic multigrid (faster than CHOLMOD from about 10,000 unknowns on,
// 0.57 x its time at 164,000, and linear in the size), else CHOLMOD; a direct solver takes
// over if the multigrid solve fails (PETSc cannot start, no convergence). `guess` is the
// initial guess on the free unknowns (empty: none). The hooks (a shared solver, a linear
// solver) are multigrid on all processes: kind amg.
FreeSolution solve_free_system(SparseMatrix& a, const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess,
                               const SolveOptions& options, const std::vector<std::int32_t>* shared_rows,
                               const std::vector<Eigen::Index>& index, const std::string& problem_name) {
  const Eigen::Index nf = rhs.size();
  const auto direct = [&] {
    if (cholmod_available()) return SolverKind::cholmod;
    return nf <= 200000 ? SolverKind::ldlt : SolverKind::cg_ichol;
  };
  FreeSolution f;
  SolverKind kind = options.solver;
  const bool automatic = kind == SolverKind::automatic;
  if (automatic) kind = nf < 20000 ? SolverKind::ldlt : amg_available() ? SolverKind::amg : direct();
  const Eigen::VectorXd* initial = guess.size() > 0 ? &guess : nullptr;
  if (shared_rows != nullptr) {
    a.makeCompressed();
    LinearSolution s = options.shared_solver(a, rhs, *shared_rows, index, initial, options.cg_tolerance);
    f.x = std::move(s.x);
    f.iterations = s.iterations;
    f.shared_residual = s.relative_residual;
  } else if (options.linear_solver) {
    a.makeCompressed();
    LinearSolution s = options.linear_solver(a, rhs, initial, options.cg_tolerance);
    f.x = std::move(s.x);
    f.iterations = s.iterations;
  } else if (kind == SolverKind::amg) {
    a.makeCompressed();
    try {
      detail::AmgSolution amg = detail::solve_amg(a, rhs, initial, options.cg_tolerance);
      f.x = std::move(amg.x);
      f.iterations = amg.iterations;
    } catch (const std::runtime_error&) {
      if (!automatic) throw;
      kind = direct();
    }
  }
  const bool hook = shared_rows != nullptr || options.linear_solver;
  f.kind = hook ? SolverKind::amg : kind;
  switch (hook ? SolverKind::automatic : kind) {
    case SolverKind::ldlt: {
      Eigen::SimplicialLDLT<SparseMatrix> ldlt;
      f.x = factor_and_solve(ldlt, a, rhs, "ldlt");
      // A zero pivot means a singular system (a part without Dirichlet boundary and c = 0).
      const Eigen::VectorXd d = ldlt.vectorD();
      if (d.minCoeff() <= 1e-12 * d.cwiseAbs().maxCoeff())
        throw std::runtime_error("problem '" + problem_name +
                                 "': the system is singular (a connected part of the mesh has no "
                                 "Dirichlet boundary while c = 0)");
      break;
    }
    case SolverKind::cholmod: {
#if defined(RGBMESH_HAVE_CHOLMOD)
      Eigen::CholmodSupernodalLLT<SparseMatrix> llt;
      // One ordering, AMD: on surface meshes of a million vertices METIS's better ordering
      // costs more to compute (6 s) than it saves in the factorization (3 s).
      llt.cholmod().nmethods = 1;
      llt.cholmod().method[0].ordering = CHOLMOD_AMD;
      // Errors only: an indefinite matrix is reported by the exception below (and, for
      // Nitsche's forms, with advice), not by a second line from CHOLMOD on stderr.
      llt.cholmod().print = 1;
      f.x = factor_and_solve(llt, a, rhs, "cholmod");
#else
      throw InputError("solver 'cholmod' is not available: rgbmesh was built without SuiteSparse");
#endif
      break;
    }
    case SolverKind::cg_ichol: {
      Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>> cg;
      cg.setTolerance(options.cg_tolerance);
      cg.setMaxIterations(static_cast<Eigen::Index>(std::max<Eigen::Index>(1000, 10 * nf)));
      cg.compute(a);
      if (cg.info() != Eigen::Success)
        throw std::runtime_error("cg: the incomplete Cholesky preconditioner failed (singular or indefinite system)");
      f.x = initial != nullptr ? Eigen::VectorXd(cg.solveWithGuess(rhs, guess))
                               : Eigen::VectorXd(cg.solve(rhs));
      f.iterations = static_cast<int>(cg.iterations());
      if (cg.info() != Eigen::Success)
        throw std::runtime_error("cg: no convergence to " + std::to_string(options.cg_tolerance) + " in " +
                                 std::to_string(cg.iterations()) + " iterations (error " + std::to_string(cg.error()) +
                                 "); the system may be singular");
      break;
    }
    case SolverKind::amg:  // solved above
    case SolverKind::automatic:
      break;
  }
  // (Each process holds only its part of a shared system: its solver measured the residual.)
  const double relative =
      shared_rows != nullptr ? f.shared_residual : (a * f.x - rhs).norm() / std::max(rhs.norm(), 1e-300);
  if (!f.x.allFinite() || !(relative <= 1e-6))
    throw std::runtime_error("problem '" + problem_name + "': the system is singular (" + to_string(kind) +
                             " left a relative residual of " + std::to_string(relative) + ")");
  return f;
}

}  // namespace

Solution solve_linear_system(SparseMatrix& a, const Eigen::VectorXd& b, const SolveOptions& options,
                             const std::string& problem_name) {
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::VectorXd guess;
  if (options.initial_guess != nullptr && options.initial_guess->size() == b.size())
    guess = *options.initial_guess;
  FreeSolution f = solve_free_system(a, b, guess, options, nullptr, {}, problem_name);
  Solution sol;
  sol.u = std::move(f.x);
  sol.solver = f.kind;
  sol.iterations = f.iterations;
  sol.solve_seconds = seconds_since(t0);
  return sol;
}

Solution solve(const SurfaceMesh& mesh, const Problem& problem, const SolveOptions& options) {
  if (!(problem.c >= 0) || !std::isfinite(problem.c))
    throw InputError("problem '" + problem.name + "': the coefficient c must be finite and >= 0, got " +
                     std::to_string(problem.c));
  Solution sol;
  auto t0 = std::chrono::steady_clock::now();
  const auto n = static_cast<Eigen::Index>(mesh.num_dofs());
  // On several processes (a shared solver and this process's part): its own triangles only.
  const bool shared = !options.share.part.empty() && options.shared_solver;
  const WorkShare everything;
  const WorkShare& share = shared ? options.share : everything;
  const Eigen::VectorXd b = shared_load_vector(mesh, problem, share);
  // (Decided together: every process refuses, not only the one whose triangles it is.)
  if (total_over(share, b.allFinite() ? 0.0 : 1.0) > 0)
    throw InputError("problem '" + problem.name +
                     "': the source or flux is not finite somewhere on the mesh");
  Constraints constraints = constrain(mesh, problem, share, shared, b);
  Eigen::VectorXd& u = constraints.u;
  sol.zero_mean = constraints.zero_mean;

  // The system K + cM on the free DOFs, assembled directly, with the fixed values moved to
  // the right-hand side; the same pass sums the vertex areas ∫ φi.
  std::vector<Eigen::Index> index(static_cast<std::size_t>(n), -1);
  Eigen::Index nf = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!constraints.fixed[i]) index[i] = nf++;
  }
  // (Decided together too: a process whose view has no free unknown still takes part in the
  // others' solve.)
  if ((shared ? total_over(share, static_cast<double>(nf)) : static_cast<double>(nf)) == 0) {
    // Every vertex is on the Dirichlet boundary (a coarse open mesh): the discrete solution is
    // the interpolant of the boundary data, and the estimators still say where to refine.
    sol.solver = options.solver == SolverKind::automatic ? SolverKind::ldlt : options.solver;
    sol.assembly_seconds = seconds_since(t0);
    sol.u = std::move(u);
    return sol;
  }
  Eigen::VectorXd rhs(nf);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (index[i] >= 0) rhs[index[i]] = b[i];
  }
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);  // ∫φ_i
  SparseMatrix a = assemble(mesh, problem, share, index, nf, u, rhs, area);
  if (sol.zero_mean) {
    // The compatible load b - (∫f / |Γ|) ∫φi (its free rows; the fixed row is dropped).
    const double shift = constraints.mean_load / total_over(share, area.sum());
    for (Eigen::Index i = 0; i < n; ++i) {
      if (index[i] >= 0) rhs[index[i]] -= shift * area[i];
    }
  }
  sol.assembly_seconds = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  Eigen::VectorXd guess;  // the initial guess on the free unknowns
  if (options.initial_guess != nullptr && options.initial_guess->size() == n) {
    guess.resize(nf);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (index[i] >= 0) guess[index[i]] = (*options.initial_guess)[i];
    }
  }
  const std::vector<std::int32_t> shared_rows =
      shared ? row_parts(mesh, share.part, index, nf) : std::vector<std::int32_t>();
  const FreeSolution f =
      solve_free_system(a, rhs, guess, options, shared ? &shared_rows : nullptr, index, problem.name);
  sol.solver = f.kind;
  sol.iterations = f.iterations;
  sol.solve_seconds = seconds_since(t0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (index[i] >= 0) u[i] = f.x[index[i]];
  }
  if (sol.zero_mean) {
    double moments[2] = {area.dot(u), area.sum()};
    if (share.sum) share.sum(moments, 2);
    u.array() -= moments[0] / moments[1];
  }
  sol.u = std::move(u);
  return sol;
}

}  // namespace rgbmesh::fem
