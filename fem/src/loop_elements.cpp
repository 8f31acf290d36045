// Loop-basis elements on a uniformly refined closed mesh (see loop_elements.hpp): the space, the
// assembly, Nitsche's boundary terms and the solves. What is computed from a solution lives
// apart: its errors and the estimator in loop_estimate.cpp, its pictures in loop_views.cpp.

#include "rgbmesh/fem/loop_elements.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "edge_key.hpp"
#include "for_each_index.hpp"
#include "loop_assembly.hpp"
#include "loop_points.hpp"
#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/timing.hpp"
#include "source_samples.hpp"

namespace rgbmesh::fem {

namespace {

using detail::dirichlet_at;
using detail::Frame;
using detail::frame_at;
using detail::laplacian_weights;
using detail::LaplacianWeights;
using detail::neumann_side;
using detail::point_source;
using detail::projected_tangent;
using detail::projection_hessian;
using detail::PointSource;
using detail::side_points;
using detail::SidePoint;

// Three sums of the control points at one point with the weights of three of the rule's
// tables (each control point read once: a point's geometry is most of the assembly's and the
// estimator's time).
std::array<Vec3, 3> patch_sums(const std::array<const Eigen::MatrixXd*, 3>& weights, Eigen::Index point,
                               const LoopSpace::Element& e, const std::vector<Vec3>& control) {
  const double *w0 = weights[0]->col(point).data(), *w1 = weights[1]->col(point).data(),
               *w2 = weights[2]->col(point).data();
  const std::vector<std::int32_t>& dofs = e.dofs;
  std::array<Vec3, 3> sum;
  for (std::size_t i = 0, n = e.surface_dofs(); i < n; ++i) {
    const Vec3& c = control[static_cast<std::size_t>(dofs[i])];
    sum[0] += w0[i] * c;
    sum[1] += w1[i] * c;
    sum[2] += w2[i] * c;
  }
  return sum;
}

// Whether p is project_to_unit_sphere, whose derivatives are known in closed form (the sphere
// problems' geometry: 23 calls of the projection a quadrature point otherwise).
bool is_unit_sphere(const Projection& p) {
  const auto* f = p.target<Vec3 (*)(const Vec3&)>();
  return f != nullptr && *f == &project_to_unit_sphere;
}

}  // namespace

namespace {

// The unit sphere's P(x) = x / |x| differentiated, with y = P(x) and s = 1 / |x|:
// dP a = (a - (y·a) y) s and D²P[a, b] = (3 (y·a)(y·b) y - (y·b) a - (y·a) b - (a·b) y) s².
Vec3 sphere_tangent(const Vec3& y, double s, const Vec3& a) { return (a - dot(y, a) * y) * s; }
Vec3 sphere_hessian(const Vec3& y, double s, const Vec3& a, const Vec3& b) {
  const double ya = dot(y, a), yb = dot(y, b);
  return (3 * ya * yb * y - yb * a - ya * b - dot(a, b) * y) * (s * s);
}

}  // namespace

// dP a at x: closed form for the unit sphere; for other projections central differences with a
// step of 1e-4 of the tangent's length (the projections are smooth on the scale of the surface;
// the error is then ~1e-8 relative).
Vec3 detail::projected_tangent(const Projection& p, const Vec3& x, const Vec3& a) {
  if (is_unit_sphere(p)) return sphere_tangent(project_to_unit_sphere(x), 1 / norm(x), a);
  const double h = 1e-4;
  return (p(x + h * a) - p(x - h * a)) * (0.5 / h);
}

// D²P[a, b] at x: closed form for the unit sphere; for other projections central differences,
// with steps of 1e-4 of |x| in space (the projections are onto surfaces of that scale: the
// error is then ~1e-8 relative).
Vec3 detail::projection_hessian(const Projection& p, const Vec3& x, const Vec3& a, const Vec3& b) {
  if (is_unit_sphere(p)) return sphere_hessian(project_to_unit_sphere(x), 1 / norm(x), a, b);
  const double s = 1e-4 * std::max(norm(x), 1e-3) / std::max({norm(a), norm(b), 1e-300});
  return (p(x + s * a + s * b) - p(x + s * a - s * b) - p(x - s * a + s * b) + p(x - s * a - s * b)) *
         (0.25 / (s * s));
}

detail::Frame detail::frame_at(const LoopSpace& space, const LoopSpace::Element& e, Eigen::Index p) {
  const LoopQuadrature& r = *e.rule;
  Frame f;
  const auto [x, xu, xv] = patch_sums({&r.value, &r.du, &r.dv}, p, e, space.control);
  f.x = x, f.xu = xu, f.xv = xv;
  f.y = f.x, f.yu = f.xu, f.yv = f.xv;
  if (space.projection) {
    const Projection& proj = *space.projection;
    if (is_unit_sphere(proj)) {  // asked once a point: laplacian_weights reads inverse_radius
      f.inverse_radius = 1 / norm(f.x);
      f.y = f.x * f.inverse_radius;
      f.yu = sphere_tangent(f.y, f.inverse_radius, f.xu);
      f.yv = sphere_tangent(f.y, f.inverse_radius, f.xv);
    } else {
      f.y = proj(f.x);
      f.yu = projected_tangent(proj, f.x, f.xu);
      f.yv = projected_tangent(proj, f.x, f.xv);
    }
  }
  const double a = dot(f.yu, f.yu), b = dot(f.yu, f.yv), c = dot(f.yv, f.yv);
  const double det = a * c - b * b;
  f.density = std::sqrt(std::max(det, 0.0));
  f.g11 = c / det, f.g12 = -b / det, f.g22 = a / det;
  return f;
}

detail::LaplacianWeights detail::laplacian_weights(const LoopSpace& space, const LoopSpace::Element& el,
                                                   Eigen::Index p, const Frame& f) {
  const LoopQuadrature& r = *el.rule;
  // Second derivatives of the surface: those of the limit surface, and through the projection
  // y = P(x): y_ab = D²P[x_a, x_b] + DP x_ab.
  auto [yuu, yuv, yvv] = patch_sums({&r.duu, &r.duv, &r.dvv}, p, el, space.control);
  if (f.inverse_radius > 0) {
    const double s = f.inverse_radius;
    yuu = sphere_hessian(f.y, s, f.xu, f.xu) + sphere_tangent(f.y, s, yuu);
    yuv = sphere_hessian(f.y, s, f.xu, f.xv) + sphere_tangent(f.y, s, yuv);
    yvv = sphere_hessian(f.y, s, f.xv, f.xv) + sphere_tangent(f.y, s, yvv);
  } else if (space.projection) {
    const Projection& proj = *space.projection;
    yuu = projection_hessian(proj, f.x, f.xu, f.xu) + projected_tangent(proj, f.x, yuu);
    yuv = projection_hessian(proj, f.x, f.xu, f.xv) + projected_tangent(proj, f.x, yuv);
    yvv = projection_hessian(proj, f.x, f.xv, f.xv) + projected_tangent(proj, f.x, yvv);
  }
  const Vec3 tu = f.g11 * f.yu + f.g12 * f.yv, tv = f.g12 * f.yu + f.g22 * f.yv;
  const Vec3 christoffel = f.g11 * yuu + (2 * f.g12) * yuv + f.g22 * yvv;  // g^{ab} y_ab
  return {f.g11, 2 * f.g12, f.g22, -dot(christoffel, tu), -dot(christoffel, tv)};
}

namespace {

// The sparsity of the Loop space's matrices: i and j are coupled when one patch holds both.
// Per DOF, the patches holding it (a CSR incidence), then each column's rows on every core.
SparseMatrix pattern(const LoopSpace& space) {
  const std::size_t n = space.num_dofs();
  std::vector<std::size_t> start(n + 1, 0);
  for (const LoopSpace::Element& e : space.elements)
    for (const std::int32_t i : e.dofs) ++start[static_cast<std::size_t>(i) + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::int32_t> holding(start.back());
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < space.elements.size(); ++e)
      for (const std::int32_t i : space.elements[e].dofs)
        holding[next[static_cast<std::size_t>(i)]++] = static_cast<std::int32_t>(e);
  }
  std::vector<std::vector<std::int32_t>> rows(n);
  detail::for_each_index(n, [&](std::size_t j) {
    // Each row once (a patch's DOFs are met by every patch holding j: about twice as many as
    // the row has), marked by a stamp unique to this column on this thread; then sorted.
    thread_local std::vector<std::uint64_t> seen;
    thread_local std::uint64_t stamp = 0;
    if (seen.size() < n) seen.resize(n, 0);
    ++stamp;
    std::vector<std::int32_t>& r = rows[j];
    for (std::size_t k = start[j]; k < start[j + 1]; ++k)
      for (const std::int32_t i : space.elements[static_cast<std::size_t>(holding[k])].dofs)
        if (seen[static_cast<std::size_t>(i)] != stamp) {
          seen[static_cast<std::size_t>(i)] = stamp;
          r.push_back(i);
        }
    std::sort(r.begin(), r.end());
  });
  SparseMatrix m(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  std::size_t nonzeros = 0;
  for (const auto& r : rows) nonzeros += r.size();
  m.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  std::size_t k = 0;
  for (std::size_t j = 0; j < n; ++j) {
    m.outerIndexPtr()[j] = static_cast<SparseMatrix::StorageIndex>(k);
    for (const std::int32_t i : rows[j]) {
      m.innerIndexPtr()[k] = i;
      m.valuePtr()[k++] = 0.0;
    }
  }
  m.outerIndexPtr()[n] = static_cast<SparseMatrix::StorageIndex>(k);
  return m;
}

// Each element's part of K + c M, of the load, of ∫φ_i, and of ∫f and ∫|f|, for a block of
// elements at a time on every core. The source comes from `f` (per point, a batch function's
// values) when given, else from problem.source.
struct LocalParts {
  Eigen::MatrixXd matrix;
  std::vector<Eigen::Index> position;  // of each local entry (column by column) in the matrix's values
  Eigen::VectorXd load, area;
  double integral = 0, magnitude = 0;
  bool degenerate = false;  // a point where the surface's metric is singular (or not finite)
  Vec3 where;               // that point
};

// N: the patch's size when known at compile time (12, regular corners: most elements), so
// that the small products run unrolled; Eigen::Dynamic otherwise.
// The bilinear form and the source: ∫ ∇u·∇v + c u v (second order) or ∫ Δu Δv + c u v
// (fourth order), and ∫ f v.
struct Form {
  bool fourth_order = false;
  double c = 0;
  ScalarField source;  // where no batch values are given
};

template <int N>
void accumulate(const LoopSpace& space, const LoopSpace::Element& e, const Form& form, const double* f,
                LocalParts& out) {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  const LoopQuadrature& r = *e.rule;
  const Eigen::Index n = static_cast<Eigen::Index>(e.dofs.size());
  Matrix matrix = Matrix::Zero(n, n);
  Vector load = Vector::Zero(n), area = Vector::Zero(n), a(n), b(n);
  out.integral = out.magnitude = 0;
  out.degenerate = false;
  for (Eigen::Index p = 0; p < static_cast<Eigen::Index>(r.size()); ++p) {
    const Frame fr = frame_at(space, e, p);
    if (!(fr.density > 0) || !std::isfinite(fr.g11 + fr.g12 + fr.g22)) {
      out.degenerate = true;
      out.where = fr.x;
      return;
    }
    const double w = r.weight[static_cast<std::size_t>(p)] * fr.density;
    const Eigen::Map<const Vector> du(r.du.col(p).data(), n), dv(r.dv.col(p).data(), n),
        phi(r.value.col(p).data(), n);
    if (form.fourth_order) {
      // Δφ_i Δφ_j: a rank-one update with the basis's Laplacians.
      const LaplacianWeights lw = laplacian_weights(space, e, p, fr);
      const Eigen::Map<const Vector> duu(r.duu.col(p).data(), n), duv(r.duv.col(p).data(), n),
          dvv(r.dvv.col(p).data(), n);
      a.noalias() = lw.a * duu + lw.b * duv + lw.c * dvv + lw.d * du + lw.e * dv;
      matrix.noalias() += (w * a) * a.transpose();
    } else {
      // ∇φ_i·∇φ_j = (du_i, dv_i) g⁻¹ (du_j, dv_j)ᵀ: a rank-two update.
      a.noalias() = (w * fr.g11) * du + (w * fr.g12) * dv;
      b.noalias() = (w * fr.g12) * du + (w * fr.g22) * dv;
      matrix.noalias() += a * du.transpose();
      matrix.noalias() += b * dv.transpose();
    }
    if (form.c != 0) matrix.noalias() += (w * form.c) * (phi * phi.transpose());
    const double source = f != nullptr ? f[p] : form.source(fr.y);
    load.noalias() += (w * source) * phi;
    area.noalias() += w * phi;
    out.integral += w * source;
    out.magnitude += w * std::abs(source);
  }
  out.matrix = matrix;
  out.load = load;
  out.area = area;
}

void local_parts(const LoopSpace& space, std::size_t element, const Form& form, const double* f,
                 const SparseMatrix& pattern, LocalParts& out) {
  const LoopSpace::Element& e = space.elements[element];
  if (e.dofs.size() == 12)
    accumulate<12>(space, e, form, f, out);
  else
    accumulate<Eigen::Dynamic>(space, e, form, f, out);
  // Where each entry goes (found here, on every core, so that the sums afterwards only add):
  // column j's rows are written into a map from row to position, which the patch's DOFs read
  // (all of them are in the column). Cheaper than a binary search per entry.
  thread_local std::vector<Eigen::Index> position_of_row;
  if (position_of_row.size() < static_cast<std::size_t>(pattern.rows()))
    position_of_row.resize(static_cast<std::size_t>(pattern.rows()));
  out.position.clear();
  for (const std::int32_t j : e.dofs) {
    for (Eigen::Index k = pattern.outerIndexPtr()[j]; k < pattern.outerIndexPtr()[j + 1]; ++k)
      position_of_row[static_cast<std::size_t>(pattern.innerIndexPtr()[k])] = k;
    for (const std::int32_t i : e.dofs) out.position.push_back(position_of_row[static_cast<std::size_t>(i)]);
  }
}

}  // namespace

detail::PointSource detail::point_source(const LoopSpace& space, const PointValues& batch) {
  PointSource s;
  if (!batch) return s;
  s.first.assign(space.elements.size() + 1, 0);
  for (std::size_t e = 0; e < space.elements.size(); ++e)
    s.first[e + 1] = s.first[e] + space.elements[e].rule->size();
  std::vector<Vec3> points(s.first.back());
  detail::for_each_index(space.elements.size(), [&](std::size_t e) {
    for (std::size_t p = 0; p < space.elements[e].rule->size(); ++p)
      points[s.first[e] + p] = frame_at(space, space.elements[e], static_cast<Eigen::Index>(p)).y;
  });
  s.values = detail::point_values(batch, points);
  return s;
}

namespace {

// The mesh completed beyond its boundary by ghost triangles (LoopBoundary::completed), as a
// ring oracle over the mesh's: ghost ids follow the vertex slots. A boundary vertex v whose
// ring runs n_0 ... n_k (k triangles, n_0 before n_k in canonical rank) gets the closed ring
// n_0 ... n_k, g(v n_k), x_1 ... x_m, g(v n_0): g(a b) the ghost beyond boundary edge ab (in
// the rings of a and b both: the ghost triangle a b g), and m = max(0, 3 - k) ghosts of v's
// own, so that the fan has max(6, k + 3) triangles. Subdivided, the fans keep their structure
// (a new boundary vertex has k = 3 and the ghosts of the next level are the midpoints of the
// edges from the boundary to the ghosts): the completion of the finer mesh is the finer
// completion. Where k = 3 along the way, Loop's boundary rules are the interior rules with
// ghosts at a + b - t (loop_basis.cpp's boundary_completion), which is why the surface's
// functions and the ghosts' together hold the completion's there.
class Completion {
 public:
  Completion() = default;
  Completion(const RgbMesh& mesh, const RingOracle& ring, const std::vector<std::int32_t>& rank)
      : first_(mesh.vertex_slots()), rank_(&rank) {
    std::vector<std::int32_t> path;
    std::vector<VertexHandle> order;
    for (const VertexHandle v : mesh.vertices())
      if (mesh.is_boundary(v)) order.push_back(v);
    std::sort(order.begin(), order.end(), [&rank](VertexHandle a, VertexHandle b) {
      return rank[static_cast<std::size_t>(a.idx)] < rank[static_cast<std::size_t>(b.idx)];
    });
    std::int32_t next = first_;
    for (const VertexHandle v : order) {
      oriented(ring, v.idx, path);
      for (const std::int32_t end : {path.front(), path.back()})
        if (across_.emplace(detail::edge_key(v.idx, end), next).second) ++next;
      const std::size_t k = path.size() - 1;
      boundary_.emplace(v.idx, BoundaryVertex{next, k});
      if (k < 3) next += static_cast<std::int32_t>(3 - k);
    }
    count_ = static_cast<std::size_t>(next - first_);
    free_.assign(count_, 0);
    for (const auto& [key, ghost] : across_) {
      const auto a = static_cast<std::int32_t>(key >> 32), b = static_cast<std::int32_t>(key & 0xffffffffu);
      const std::size_t ka = boundary_.at(a).triangles, kb = boundary_.at(b).triangles;
      free_[static_cast<std::size_t>(ghost - first_)] = (ka == 3 || kb == 3) && ka != 2 && kb != 2;
    }
  }

  std::size_t count() const { return count_; }
  bool is_ghost(std::int32_t id) const { return id >= first_; }
  // Whether a ghost's function is one of the space's: one beyond a boundary edge with an end of
  // three triangles and none of two. Measured on the square (64 cells a side, H1 errors; Loop's
  // rules 9.5e-4): these 1.0e-4, with the residual estimate 5 times the error as with Loop's
  // rules. With the ghosts next to the corners of two triangles too, 2.8e-5, but the estimate
  // 80 times the error: smooth in the completion's parameters, they are not on the surface,
  // whose boundary rules bend the parameters at such a corner, and their Laplacians there are
  // large. Between two regular ends only, 1.9e-4. A corner's own ghosts and those between two
  // irregular ends inflated the estimate 10 to 15 times on public meshes (mech-holes-shark,
  // CGAL's cylinder) and slowed BoomerAMG 20-fold, for no accuracy.
  bool is_free(std::int32_t id) const { return free_[static_cast<std::size_t>(id - first_)] != 0; }

  bool ring(const RingOracle& mesh_ring, std::int32_t v, std::vector<std::int32_t>& out) const {
    if (mesh_ring(v, out)) return true;
    if (v >= first_) throw std::logic_error("Completion: a ghost's ring was asked for");
    oriented(mesh_ring, v, out);
    const std::int32_t front = out.front(), back = out.back();
    const std::size_t k = out.size() - 1;
    out.push_back(across_.at(detail::edge_key(v, back)));
    const std::int32_t own = boundary_.at(v).first_own;
    for (std::size_t i = 0; i + k < 3; ++i) out.push_back(own + static_cast<std::int32_t>(i));
    out.push_back(across_.at(detail::edge_key(v, front)));
    return true;
  }

 private:
  // A boundary vertex's ring as the mesh gives it, turned so that it starts at the boundary
  // neighbour of lower canonical rank (the ghosts' numbers then do not depend on handles).
  void oriented(const RingOracle& mesh_ring, std::int32_t v, std::vector<std::int32_t>& out) const {
    if (mesh_ring(v, out)) throw std::logic_error("Completion: an interior vertex taken for a boundary one");
    const auto r = [this](std::int32_t w) { return (*rank_)[static_cast<std::size_t>(w)]; };
    if (r(out.back()) < r(out.front())) std::reverse(out.begin(), out.end());
  }

  std::int32_t first_ = 0;
  std::size_t count_ = 0;
  const std::vector<std::int32_t>* rank_ = nullptr;
  std::unordered_map<std::uint64_t, std::int32_t> across_;  // boundary edge -> its ghost
  struct BoundaryVertex {
    std::int32_t first_own = 0;  // its own ghosts' first id
    std::size_t triangles = 0;
  };
  std::unordered_map<std::int32_t, BoundaryVertex> boundary_;
  std::vector<char> free_;  // per ghost
};

}  // namespace

LoopSpace build_loop_space(RgbMesh& mesh, std::optional<Projection> projection,
                           const LoopQuadratureOptions& quadrature, LoopBoundary boundary) {
  LoopSpace space;
  space.projection = std::move(projection);
  space.level = -1;
  for (const TriangleHandle t : mesh.triangles()) {
    if (space.level < 0) space.level = mesh.level(t);
    if (mesh.color(t) != Color::green || mesh.level(t) != space.level)
      throw InputError("Loop elements need a uniformly refined mesh for now, but triangle " +
                       std::to_string(t.idx) + " is not a green triangle of level " +
                       std::to_string(space.level));
  }
  if (quadrature.points_per_direction < 0 || quadrature.points_per_direction > 20 ||
      quadrature.extraordinary_depth < 0 || quadrature.extraordinary_depth > 20)
    throw std::invalid_argument("build_loop_space: points per direction in [0, 20], depth in [0, 20]");
  mesh.compute_limits();
  // Numbered canonically (canonical.hpp), each triangle's corners from its lowest-numbered one:
  // the parametrization of each element, hence its quadrature points, and every sum then
  // depend on the mesh only, not on its handles (a resumed run repeats the uninterrupted one).
  const std::vector<VertexHandle> vertex_order = canonical_vertex_order(mesh);
  std::vector<std::int32_t> rank(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  for (std::size_t i = 0; i < vertex_order.size(); ++i)
    rank[static_cast<std::size_t>(vertex_order[i].idx)] = static_cast<std::int32_t>(i);
  // Patches are gathered by vertex slots (the mesh's vertex numbers, which messages name; a
  // base vertex's is its index in the input), then turned into DOFs.
  const RingOracle ring = [&mesh](std::int32_t slot, std::vector<std::int32_t>& out) {
    thread_local VertexStar star;  // the patches are gathered on every core
    mesh.star(VertexHandle(slot), star);
    out.clear();
    for (const VertexHandle w : star.neighbors) out.push_back(w.idx);
    return !star.boundary;
  };
  const LoopFeatures features = loop_mesh_features(mesh, space.level);
  const bool completed = boundary == LoopBoundary::completed;
  if (completed && mesh.has_sharp_features())
    throw InputError(
        "Loop elements: the completed boundary (LoopBoundary::completed) does not take sharp features; "
        "use LoopBoundary::loop_rules");
  const Completion completion = completed ? Completion(mesh, ring, rank) : Completion();
  const RingOracle completed_ring = [&ring, &completion](std::int32_t v, std::vector<std::int32_t>& out) {
    return completion.ring(ring, v, out);
  };
  const bool ghosts = boundary == LoopBoundary::ghost_ring;
  const bool sides = boundary != LoopBoundary::refuse;
  std::vector<std::array<VertexHandle, 3>> element_corners;
  std::vector<TriangleHandle> element_triangles;
  std::vector<std::int32_t> element_of_slot(static_cast<std::size_t>(mesh.triangle_slots()), -1);
  for (const TriangleHandle t : canonical_triangle_order(mesh, vertex_order)) {
    auto corners = mesh.triangle_vertices(t);
    const bool at_boundary =
        mesh.is_boundary(corners[0]) || mesh.is_boundary(corners[1]) || mesh.is_boundary(corners[2]);
    if (at_boundary && boundary == LoopBoundary::refuse)
      throw InputError("Loop elements: the triangle of vertices " + std::to_string(corners[0].idx) + ", " +
                       std::to_string(corners[1].idx) + ", " + std::to_string(corners[2].idx) +
                       " reaches the boundary, and this space is for closed surfaces");
    if (ghosts && at_boundary) continue;
    const auto by_rank = [&](VertexHandle a, VertexHandle b) {
      return rank[static_cast<std::size_t>(a.idx)] < rank[static_cast<std::size_t>(b.idx)];
    };
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end(), by_rank), corners.end());
    element_of_slot[static_cast<std::size_t>(t.idx)] = static_cast<std::int32_t>(element_triangles.size());
    element_corners.push_back(corners);
    element_triangles.push_back(t);
  }
  // Each patch and its rule on every core (the rules' cache is shared); a refusal names the
  // first triangle in canonical order, whatever the number of threads.
  std::vector<LoopPatch> patches(element_triangles.size());
  std::vector<std::vector<std::int32_t>> ghosts_of(element_triangles.size());
  std::vector<std::shared_ptr<const LoopQuadrature>> rules(element_triangles.size());
  std::vector<std::string> refused(element_triangles.size());
  detail::for_each_index(element_triangles.size(), [&](std::size_t e) {
    const auto& c = element_corners[e];
    try {
      patches[e] = gather_loop_patch({c[0].idx, c[1].idx, c[2].idx}, ring, features);
      // Ghost functions reach only the triangles with a corner on the boundary (a ghost is in
      // no other corner's ring, and the other vertices of the completed patch enter the
      // triangle's subdivision through the interior edge rule alone).
      if (completed && !patches[e].closed()) {
        const LoopPatch whole = gather_loop_patch({c[0].idx, c[1].idx, c[2].idx}, completed_ring);
        std::vector<int> rows;
        for (std::size_t i = 0; i < whole.vertices.size(); ++i)
          if (completion.is_ghost(whole.vertices[i]) && completion.is_free(whole.vertices[i])) {
            rows.push_back(static_cast<int>(i));
            ghosts_of[e].push_back(whole.vertices[i]);
          }
        rules[e] = loop_quadrature(patches[e], whole, rows, quadrature);
      } else {
        rules[e] = loop_quadrature(patches[e], quadrature);
      }
    } catch (const InputError& error) {
      refused[e] = error.what();
    }
  });
  for (const std::string& why : refused)
    if (!why.empty()) throw InputError(why);
  if (patches.empty())
    throw InputError(
        "Loop elements: no triangle has its three corners inside the mesh (the elements need a "
        "ring of triangles around them whose vertices carry control values only)");
  // The DOFs: the vertices of some patch (on a closed mesh, every vertex), in canonical order.
  const std::size_t slots = static_cast<std::size_t>(mesh.vertex_slots());
  std::vector<char> used(slots + completion.count(), 0);
  for (std::size_t e = 0; e < patches.size(); ++e) {
    for (const std::int32_t v : patches[e].vertices) used[static_cast<std::size_t>(v)] = 1;
    for (const std::int32_t g : ghosts_of[e]) used[static_cast<std::size_t>(g)] = 1;
  }
  std::vector<std::int32_t> dof_of_id(used.size(), -1);
  for (const VertexHandle v : vertex_order) {
    if (!used[static_cast<std::size_t>(v.idx)]) continue;
    dof_of_id[static_cast<std::size_t>(v.idx)] = static_cast<std::int32_t>(space.vertex.size());
    space.vertex.push_back(v);
    space.control.push_back(mesh.control_point(v, space.level));
  }
  // The ghosts after the vertices, in the order the completion numbered them (canonical).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t id = slots; id < used.size(); ++id) {
    if (!used[id]) continue;
    dof_of_id[id] = static_cast<std::int32_t>(space.vertex.size());
    space.vertex.push_back(VertexHandle());
    space.control.push_back(Vec3{nan, nan, nan});
  }
  space.dof_of_vertex.assign(dof_of_id.begin(), dof_of_id.begin() + static_cast<std::ptrdiff_t>(slots));
  for (std::size_t e = 0; e < patches.size(); ++e) {
    LoopPatch& patch = patches[e];
    const TriangleHandle t = element_triangles[e];
    if (sides) {  // the element's sides towards triangles that are no elements
      for (int k = 0; k < 3; ++k) {
        const VertexHandle a(patch.vertices[static_cast<std::size_t>(k)]),
            b(patch.vertices[static_cast<std::size_t>((k + 1) % 3)]);
        for (const EdgeHandle edge : mesh.triangle_edges(t)) {
          const auto& ends = mesh.edge_vertices(edge);
          if (!((ends[0] == a && ends[1] == b) || (ends[0] == b && ends[1] == a))) continue;
          const TriangleHandle other = mesh.other_triangle(edge, t);
          if (!other.valid() || element_of_slot[static_cast<std::size_t>(other.idx)] < 0)
            space.boundary.push_back({e, k});
        }
      }
    }
    std::vector<std::int32_t> dofs;
    for (const std::int32_t v : patch.vertices) dofs.push_back(dof_of_id[static_cast<std::size_t>(v)]);
    for (const std::int32_t g : ghosts_of[e]) dofs.push_back(dof_of_id[static_cast<std::size_t>(g)]);
    space.elements.push_back({t, std::move(dofs), std::move(rules[e])});
  }
  // The seams: elements meeting along an infinitely sharp edge, each side running the other way.
  if (mesh.has_sharp_features()) {
    for (std::size_t e = 0; e < space.elements.size(); ++e) {
      const TriangleHandle t = space.elements[e].triangle;
      const auto corners = element_corners[e];
      for (int k = 0; k < 3; ++k) {
        const EdgeHandle edge = mesh.find_edge(corners[static_cast<std::size_t>(k)],
                                               corners[static_cast<std::size_t>((k + 1) % 3)]);
        if (mesh.is_boundary(edge) || !loop::is_infinitely_sharp(mesh.sharpness(edge))) continue;
        const TriangleHandle other = mesh.other_triangle(edge, t);
        const std::int32_t f = element_of_slot[static_cast<std::size_t>(other.idx)];
        if (f < static_cast<std::int32_t>(e)) continue;  // once per edge; none beyond a ghost ring
        const auto& theirs = element_corners[static_cast<std::size_t>(f)];
        int j = 0;
        while (theirs[static_cast<std::size_t>(j)] != corners[static_cast<std::size_t>((k + 1) % 3)]) ++j;
        space.seams.push_back({{e, static_cast<std::size_t>(f)}, {k, j}, {0.0, 1.0}, {1.0, 0.0}});
      }
    }
  }
  return space;
}

LoopFeatures loop_mesh_features(const RgbMesh& mesh, int level) {
  LoopFeatures out;
  if (!mesh.has_sharp_features()) return out;
  const SharpFeatures& tags = mesh.sharp_features();
  out.method = tags.method;
  const bool chaikin = tags.method == CreaseMethod::chaikin;
  const std::int32_t base = static_cast<std::int32_t>(mesh.num_base_vertices());
  out.at = [&mesh, &tags, level, chaikin, base](std::int32_t v, const std::vector<std::int32_t>& ring,
                                                LoopVertexFeatures& f) {
    thread_local VertexStar star;  // the patches are gathered on every core
    const VertexHandle vh(v);
    mesh.star(vh, star);
    f.sharpness = mesh.vertex_sharpness(vh, level);
    f.edges.assign(ring.size(), 0.0f);
    f.order.clear();
    // Chaikin's averages at a base vertex sum its edges' sharpness in the order of their sharp
    // base edges, as the mesh does: each piece is traced up to its base edge.
    if (chaikin && v < base) f.order.assign(ring.size(), std::numeric_limits<std::int32_t>::max());
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const auto at = std::find_if(star.neighbors.begin(), star.neighbors.end(),
                                   [&](VertexHandle w) { return w.idx == ring[i]; });
      if (at == star.neighbors.end())
        throw std::logic_error("loop_mesh_features: a ring that is not the star's");
      f.edges[i] = mesh.sharpness(star.edges[static_cast<std::size_t>(at - star.neighbors.begin())]);
      if (f.order.empty() || !loop::is_semi_sharp(f.edges[i])) continue;
      VertexHandle w(ring[i]);
      while (w.idx >= base) {
        const auto& p = mesh.parents(w);
        w = p[0] == vh ? p[1] : p[0];
      }
      const SharpEdge key{std::min(v, w.idx), std::max(v, w.idx), 0.0f};
      const auto it = std::lower_bound(
          tags.edges.begin(), tags.edges.end(), key,
          [](const SharpEdge& x, const SharpEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
      if (it != tags.edges.end() && it->a == key.a && it->b == key.b)
        f.order[i] = static_cast<std::int32_t>(it - tags.edges.begin());
    }
  };
  return out;
}

LoopPoint loop_point(const LoopSpace& space, std::size_t element, std::size_t point) {
  const LoopSpace::Element& e = space.elements[element];
  const Eigen::Index p = static_cast<Eigen::Index>(point);
  const Frame f = frame_at(space, e, p);
  LoopPoint out{f.y, f.yu, f.yv, f.density, {}};
  for (std::size_t i = 0; i < e.dofs.size(); ++i) {
    const double du = e.rule->du(static_cast<Eigen::Index>(i), p),
                 dv = e.rule->dv(static_cast<Eigen::Index>(i), p);
    out.gradient.push_back(f.gradient(du, dv));
  }
  return out;
}

namespace {

// Where the limit surface's tangents are parallel (or not finite) the Loop basis has no
// gradient. On a base mesh that passed the input checks this is the limit surface itself being
// singular: Loop's smoothing folds cap or needle triangles that lie across a crease (openscad's
// bad-stl-wing.stl reaches it after 48 adaptive cycles, the cells gathering on such a point),
// and its boundary rules fold a coarse boundary that turns sharply (CGAL's triangular_hole.off,
// a triangle with a triangular hole, has such a point inside the hole's corner).
std::string degenerate_surface_message(const LoopSpace& space, const LoopSpace::Element& e,
                                       const Vec3& where) {
  std::ostringstream text;
  text
      << "Loop elements: the limit surface is singular (its tangents parallel, or not finite) near ("
      << where.x << ", " << where.y << ", " << where.z << "), on the cell whose corners are vertices "
      << space.vertex[static_cast<std::size_t>(e.dofs[0])].idx << ", "
      << space.vertex[static_cast<std::size_t>(e.dofs[1])].idx << ", "
      << space.vertex[static_cast<std::size_t>(e.dofs[2])].idx
      << ". Usual causes: coincident or collinear control points (--repair removes them), cap or needle "
         "triangles across a crease of the input, or a boundary of few edges that turns sharply (Loop's "
         "smoothing and boundary rules fold the surface there): --element p2 copes with those; or remesh the "
         "input finer there";
  return text.str();
}

detail::LoopSystem assemble_loop(const LoopSpace& space, const Form& form, const PointSource& f,
                                 const std::string& name) {
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::Index n = static_cast<Eigen::Index>(space.num_dofs());
  detail::LoopSystem out;
  out.a = pattern(space);
  out.b = Eigen::VectorXd::Zero(n);
  out.area = Eigen::VectorXd::Zero(n);
  bool finite = true;
  constexpr std::size_t kBlock = 2048;
  std::vector<LocalParts> parts(kBlock);
  for (std::size_t begin = 0; begin < space.elements.size(); begin += kBlock) {
    const std::size_t count = std::min(kBlock, space.elements.size() - begin);
    // Blocks of 64 elements: 2048 in blocks of for_each_index's default 4096 would be one block,
    // on one thread.
    detail::for_each_index(
        count, [&](std::size_t i) { local_parts(space, begin + i, form, f.of(begin + i), out.a, parts[i]); }, 64);
    for (std::size_t i = 0; i < count; ++i) {  // in element order: the same sums on any number of cores
      const LoopSpace::Element& e = space.elements[begin + i];
      const LocalParts& lp = parts[i];
      if (lp.degenerate) throw InputError(degenerate_surface_message(space, e, lp.where));
      finite = finite && std::isfinite(lp.integral) && std::isfinite(lp.magnitude);
      out.integral += lp.integral;
      out.magnitude += lp.magnitude;
      for (std::size_t jl = 0; jl < e.dofs.size(); ++jl) {
        const Eigen::Index j = e.dofs[jl];
        out.b(j) += lp.load(static_cast<Eigen::Index>(jl));
        out.area(j) += lp.area(static_cast<Eigen::Index>(jl));
      }
      double* values = out.a.valuePtr();
      const double* local = lp.matrix.data();  // column by column, as the positions
      for (std::size_t k = 0; k < lp.position.size(); ++k) values[lp.position[k]] += local[k];
    }
  }
  if (!finite) throw InputError("problem '" + name + "': the source is not finite somewhere on the surface");
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace

// The automatic choice differs from P1's and P2's: the wider stencil fills a simplicial LDLT
// factor far more (uniform space, 37 entries a row, 10,242 unknowns: 0.52 s against CHOLMOD's
// supernodal 0.16 s), and BoomerAMG pays off later, by the matrix's entries rather than its
// rows. Uniform space: 40,962 unknowns, CHOLMOD 0.8 s, AMG 1.05 s; 163,842: CHOLMOD 6.4 s, AMG
// 5.2 s. Adaptive (truncated basis, ~190 entries a row; sphere-peak, 2026-12-05, whole cycles
// of `rgbmesh adapt`, same script): 35,582 unknowns, CHOLMOD 7.7 s, AMG 9.0 s; 48,164: 11.8 s,
// 13.4 s; 66,078 (12.5·10^6 entries): 17.5 s, 19.1 s, the run's peak memory 993 MB against
// 752 MB. CHOLMOD's time grows as N^1.4 there and AMG's as N^1.2, so they cross near 10^5
// unknowns (~1.9·10^7 entries); from 1.5·10^7 entries AMG is about as fast and lighter.
// Narrow rows (at most 60 entries: the uniform space, the truncated hierarchical basis) take
// AMG from 10,000 unknowns (2026-12-07, the solve alone, same script: uniform 40,962 unknowns
// CHOLMOD 1.48 s, AMG 0.49 s in 11 iterations; adaptive sphere-peak in the truncated
// hierarchical basis, 21,854: 0.54 s, 0.35 s; 49,073: 1.85 s, 0.95 s in 32. With aggressive
// coarsening (amg_options), whole runs with either solver: 7,148 unknowns CHOLMOD 0.13 s, AMG
// 0.064 s; 11,740: 0.29 s, 0.12 s; 24,979: 0.65 s, 0.23 s; 52,954: 1.69 s, 0.63 s. Below
// 10,000 the once-per-run start of PETSc, ~0.3 s, outweighs what AMG saves.)
SolveOptions detail::loop_solver(const SolveOptions& options, const SparseMatrix& a) {
  SolveOptions chosen = options;
  const Eigen::Index n = a.rows();
  const bool narrow = a.nonZeros() <= 60 * n;
  const bool large = n >= 100000 || (n >= 10000 && narrow) || (n >= 20000 && a.nonZeros() >= 15000000);
  if (chosen.solver == SolverKind::automatic && !chosen.linear_solver) {
    if (amg_available() && large)
      chosen.solver = SolverKind::amg;
    else if (cholmod_available() && n < 100000)
      chosen.solver = SolverKind::cholmod;
  }
  return chosen;
}

double detail::largest_ratio(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (!a.allFinite() || !b.allFinite())
    throw InputError(
        "Loop elements: a boundary element's geometry is degenerate (its Nitsche constant is not finite)");
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(a);
  const Eigen::VectorXd& lambda = eigen.eigenvalues();
  const double cut = 1e-10 * std::max(lambda.maxCoeff(), 0.0);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (lambda(i) > cut) kept.push_back(i);
  if (kept.empty()) return 0;
  Eigen::MatrixXd scaled(a.rows(), static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k)
    scaled.col(static_cast<Eigen::Index>(k)) = eigen.eigenvectors().col(kept[k]) / std::sqrt(lambda(kept[k]));
  const Eigen::MatrixXd reduced = scaled.transpose() * b * scaled;
  const double ratio = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(reduced, Eigen::EigenvaluesOnly)
                           .eigenvalues()
                           .maxCoeff();
  if (!std::isfinite(ratio))
    throw InputError(
        "Loop elements: a boundary element's geometry is degenerate (its Nitsche constant is not finite)");
  return ratio;
}

void detail::check_nitsche_options(const std::string& name, double factor, double guarantee,
                                   const std::string& option, int edge_points) {
  if (!(factor > guarantee) || !std::isfinite(factor))
    throw InputError("problem '" + name + "': Nitsche's penalty factor " + std::to_string(factor) +
                     " is not above " + std::to_string(static_cast<int>(guarantee)) +
                     ", below which the form need not be coercive (" + option + ")");
  if (edge_points < 1 || edge_points > 16)
    throw std::invalid_argument("Nitsche's terms: edge points in [1, 16], got " +
                                std::to_string(edge_points));
}

detail::SideParameters detail::side_parameters(int edge, double t) {
  switch (edge) {
    case 0:
      return {t, 0, 1, 0};  // corner 0 -> 1
    case 1:
      return {1 - t, t, -1, 1};  // corner 1 -> 2
    case 2:
      return {0, 1 - t, 0, -1};  // corner 2 -> 0
  }
  throw std::invalid_argument("side_parameters: edge in [0, 2]");
}

void detail::require_smooth(const LoopSpace& space, const std::string& name) {
  if (!space.seams.empty())
    throw InputError(
        "problem '" + name +
        "': a fourth-order problem needs C1 functions, and Loop's are only continuous across the "
        "mesh's infinitely sharp edges; make those edges semi-sharp (sharpness below 10) or smooth");
}

void detail::add_local(SparseMatrix& a, const std::vector<std::int32_t>& dofs, const Eigen::MatrixXd& local) {
  for (std::size_t j = 0; j < dofs.size(); ++j)
    for (std::size_t i = 0; i < dofs.size(); ++i)
      a.coeffRef(dofs[i], dofs[j]) += local(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
}

Solution detail::solve_nitsche_system(LoopSystem& s, const SolveOptions& options, const std::string& name,
                                      double penalty, const std::string& option) {
  Solution sol;
  try {
    sol = solve_linear_system(s.a, s.b, loop_solver(options, s.a), name);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("not positive definite") == std::string::npos) throw;
    throw InputError("problem '" + name + "': with Nitsche's penalty " + std::to_string(penalty) +
                     " the system is not positive definite on this mesh; raise the penalty (" + option +
                     "; 2-4 times more costs little accuracy)");
  }
  sol.assembly_seconds = s.seconds;
  return sol;
}

detail::LoopSystem detail::assemble_loop_system(const LoopSpace& space, bool fourth_order, double c,
                                                const ScalarField& source, const PointValues& batch,
                                                const std::string& name) {
  return assemble_loop(space, {fourth_order, c, source}, point_source(space, batch), name);
}

namespace {

// solve_loop_biharmonic is for closed surfaces: on a space with a boundary its form would
// impose natural conditions silently.
void require_closed(const LoopSpace& space, const std::string& name) {
  if (!space.boundary.empty())
    throw InputError(
        "problem '" + name +
        "': Loop elements solve the surface biharmonic on closed surfaces only; on a mesh with a "
        "boundary they solve -Δu + c u = f with Dirichlet data (solve_loop) and the clamped plate "
        "(solve_clamped_plate)");
}

// Nitsche's terms for u = g on the boundary sides (see LoopNitscheOptions), added to the
// system: at each Gauss point of a side, the basis, its co-normal derivative ∂ₘφ = ∇_Γφ · m
// with m = y_t × n / |y_t| (outward: the parameter triangle runs counter-clockwise about the
// normal n = y_u × y_v / |y_u × y_v|), and g. A Neumann side (problem.is_neumann at its
// midpoint) takes the flux instead: ∫_Γ h v, no Nitsche terms.
void add_boundary_terms(const LoopSpace& space, const Problem& problem, const LoopNitscheOptions& o,
                        detail::LoopSystem& s);

}  // namespace

std::vector<detail::SidePoint> detail::side_points(const LoopSpace& space, const LoopSpace::Side& side,
                                                   const std::vector<double>& gauss_t) {
  const LoopSpace::Element& e = space.elements[side.element];
  std::vector<SidePoint> out;
  for (const double t : gauss_t) {
    const detail::SideParameters at = detail::side_parameters(side.edge, t);
    const LoopBasisAt basis = loop_rule_basis(*e.rule, at.u, at.v);
    Vec3 x, xu, xv;
    for (std::size_t i = 0; i < e.surface_dofs(); ++i) {
      const Vec3& c = space.control[static_cast<std::size_t>(e.dofs[i])];
      const Eigen::Index k = static_cast<Eigen::Index>(i);
      x += basis.value(k) * c, xu += basis.du(k) * c, xv += basis.dv(k) * c;
    }
    Vec3 y = x, yu = xu, yv = xv;
    if (space.projection) {
      y = (*space.projection)(x);
      yu = projected_tangent(*space.projection, x, xu);
      yv = projected_tangent(*space.projection, x, xv);
    }
    const double a = dot(yu, yu), b = dot(yu, yv), c = dot(yv, yv), det = a * c - b * b;
    const Vec3 tangent = at.du * yu + at.dv * yv;
    SidePoint p;
    p.speed = norm(tangent);
    const Vec3 normal = (1.0 / std::sqrt(det)) * cross(yu, yv);
    const Vec3 m = (1.0 / p.speed) * cross(tangent, normal);
    // ∇_Γφ · m = (g^{1b} φ_b) y_u · m + (g^{2b} φ_b) y_v · m.
    const double um = dot(yu, m), vm = dot(yv, m);
    p.dm = ((c * um - b * vm) / det) * basis.du + ((a * vm - b * um) / det) * basis.dv;
    p.value = basis.value;
    p.y = y;
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<double> detail::dirichlet_at(const Problem& problem, const std::vector<Vec3>& points) {
  if (problem.dirichlet_values) return detail::point_values(problem.dirichlet_values, points);
  std::vector<double> g(points.size(), 0.0);
  if (problem.dirichlet)
    for (std::size_t i = 0; i < points.size(); ++i) g[i] = problem.dirichlet(points[i]);
  return g;
}

bool detail::neumann_side(const LoopSpace& space, const LoopSpace::Side& side, const Problem& problem) {
  return problem.is_neumann && problem.is_neumann(side_points(space, side, {0.5}).front().y);
}

void detail::add_loop_boundary_terms(const LoopSpace& space, const Problem& problem,
                                     const LoopNitscheOptions& options, LoopSystem& s) {
  add_boundary_terms(space, problem, options, s);
}

namespace {

void add_boundary_terms(const LoopSpace& space, const Problem& problem, const LoopNitscheOptions& o,
                        detail::LoopSystem& s) {
  detail::check_nitsche_options(problem.name, o.penalty, 1, "LoopNitscheOptions::penalty, 4 by default",
                                o.edge_points);
  if (problem.dirichlet && problem.dirichlet_values)
    throw InputError("problem '" + problem.name +
                     "': both dirichlet and dirichlet_values are set (give one)");
  std::vector<double> gauss_t, gauss_w;
  gauss_legendre(o.edge_points, gauss_t, gauss_w);
  using Point = SidePoint;
  struct SideTerms {
    std::size_t element = 0;
    std::vector<Point> points;
    std::vector<Vec3> where;
    std::vector<double> g;
    double length = 0;
  };
  // The Dirichlet sides of each element, with their points; Neumann sides go to the load.
  std::map<std::size_t, std::vector<SideTerms>> dirichlet_sides;
  for (const LoopSpace::Side& side : space.boundary) {
    const LoopSpace::Element& e = space.elements[side.element];
    const Eigen::Index n = static_cast<Eigen::Index>(e.dofs.size());
    SideTerms terms;
    terms.element = side.element;
    terms.points = side_points(space, side, gauss_t);
    for (std::size_t q = 0; q < gauss_t.size(); ++q) {
      terms.length += gauss_w[q] * terms.points[q].speed;
      terms.where.push_back(terms.points[q].y);
    }
    if (neumann_side(space, side, problem)) {
      for (std::size_t q = 0; q < terms.points.size(); ++q) {
        const double h = problem.neumann_flux ? problem.neumann_flux(terms.where[q]) : 0.0;
        if (!std::isfinite(h))
          throw InputError("problem '" + problem.name + "': the Neumann flux is not finite on the boundary");
        const Eigen::VectorXd load = (gauss_w[q] * terms.points[q].speed * h) * terms.points[q].value;
        for (Eigen::Index i = 0; i < n; ++i) s.b(e.dofs[static_cast<std::size_t>(i)]) += load(i);
      }
      continue;
    }
    dirichlet_sides[side.element].push_back(std::move(terms));
  }
  // g at every Dirichlet point, in one call of a batch function.
  std::vector<Vec3> all_points;
  for (const auto& [element, sides] : dirichlet_sides)
    for (const SideTerms& side : sides)
      all_points.insert(all_points.end(), side.where.begin(), side.where.end());
  if (all_points.empty() && problem.c == 0)
    throw InputError(
        "problem '" + problem.name +
        "': every boundary side is Neumann and c = 0, so the solution is defined up to a constant; "
        "make a side Dirichlet or use c > 0");
  const std::vector<double> all_g = dirichlet_at(problem, all_points);
  std::size_t next = 0;
  for (auto& [element, sides] : dirichlet_sides)
    for (SideTerms& side : sides)
      for (std::size_t q = 0; q < side.where.size(); ++q) {
        if (!std::isfinite(all_g[next]))
          throw InputError("problem '" + problem.name +
                           "': the Dirichlet data is not finite on the boundary");
        side.g.push_back(all_g[next++]);
      }
  for (const auto& [element, sides] : dirichlet_sides) {
    const LoopSpace::Element& e = space.elements[element];
    const Eigen::Index n = static_cast<Eigen::Index>(e.dofs.size());
    // The penalty γ = f C, C the largest ratio h ∫_∂T (∂ₘv)² / ∫_T |∇v|² over the element's
    // functions: with f > 1 the symmetric terms take less than the element's energy (Young's
    // inequality), so the form is coercive.
    Eigen::MatrixXd energy = Eigen::MatrixXd::Zero(n, n), on_sides = energy;
    for (std::size_t p = 0; p < e.rule->size(); ++p) {
      const LoopPoint at = loop_point(space, element, p);
      const double w = e.rule->weight[p] * at.density;
      for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i)
          energy(i, j) +=
              w * dot(at.gradient[static_cast<std::size_t>(i)], at.gradient[static_cast<std::size_t>(j)]);
    }
    for (const SideTerms& side : sides)
      for (std::size_t q = 0; q < side.points.size(); ++q)
        on_sides.noalias() += (gauss_w[q] * side.points[q].speed * side.length) *
                              (side.points[q].dm * side.points[q].dm.transpose());
    const double gamma = o.penalty * detail::largest_ratio(energy, on_sides);
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(n, n);
    for (const SideTerms& side : sides) {
      const double beta = gamma / side.length;
      for (std::size_t q = 0; q < side.points.size(); ++q) {
        const Point& p = side.points[q];
        const double w = gauss_w[q] * p.speed;
        local.noalias() -= w * (p.dm * p.value.transpose() + p.value * p.dm.transpose());
        local.noalias() += (w * beta) * (p.value * p.value.transpose());
        const Eigen::VectorXd load = (w * side.g[q]) * (beta * p.value - p.dm);
        for (Eigen::Index i = 0; i < n; ++i) s.b(e.dofs[static_cast<std::size_t>(i)]) += load(i);
      }
    }
    detail::add_local(s.a, e.dofs, local);
  }
}

}  // namespace

Solution solve_loop(const LoopSpace& space, const Problem& problem, const SolveOptions& options,
                    const LoopNitscheOptions& nitsche) {
  if (!(problem.c >= 0) || !std::isfinite(problem.c))
    throw InputError("problem '" + problem.name + "': the coefficient c must be finite and >= 0");
  if (!problem.source && !problem.source_values)
    throw InputError("problem '" + problem.name + "' has no source");
  detail::LoopSystem s = assemble_loop(space, {false, problem.c, problem.source},
                                       point_source(space, problem.source_values), problem.name);
  if (!space.boundary.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    add_boundary_terms(space, problem, nitsche, s);
    s.seconds += seconds_since(t0);
    // The ghosts' functions of a completed boundary, small inside the domain, slow BoomerAMG
    // down (153 iterations against 27 on mech-holes-shark refined once, about 21,000
    // unknowns), where CHOLMOD solves it in less time than AMG takes without them: direct
    // below 100,000 unknowns.
    SolveOptions chosen = options;
    const bool ghosts = std::any_of(space.elements.begin(), space.elements.end(),
                                    [](const LoopSpace::Element& e) { return e.rule->extension != nullptr; });
    if (ghosts && chosen.solver == SolverKind::automatic && !chosen.linear_solver && cholmod_available() &&
        s.a.rows() < 100000)
      chosen.solver = SolverKind::cholmod;
    return detail::solve_nitsche_system(s, chosen, problem.name, nitsche.penalty,
                                        "LoopNitscheOptions::penalty, 4 by default");
  }
  return detail::solve_closed_loop_system(s, problem, options, Eigen::VectorXd::Ones(s.a.rows()));
}

Solution detail::solve_closed_loop_system(LoopSystem& s, const Problem& problem, const SolveOptions& options,
                                          const Eigen::VectorXd& constant) {
  const bool zero_mean = problem.c == 0;
  Eigen::Index pinned = 0;
  if (zero_mean) {
    // A closed surface with c = 0: solutions differ by constants (which the Loop space holds:
    // its functions sum to one) and exist only for a source of zero mean; the discrete load is
    // then made exactly compatible (orthogonal to the constant's coefficients), one value
    // fixed where the constant's coefficient is not zero, the result shifted to zero mean.
    if (std::abs(s.integral) > problem.mean_tolerance * s.magnitude)
      throw InputError("problem '" + problem.name +
                       "': on a closed surface with c = 0 the source must have zero mean, but ∫f = " +
                       std::to_string(s.integral) + "; use c > 0, or subtract the mean");
    const double measure = s.area.dot(constant);
    s.b -= (s.b.dot(constant) / measure) * s.area;
    while (constant(pinned) == 0) ++pinned;
    for (Eigen::Index j = 0; j < s.a.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(s.a, j); it; ++it)
        if (it.row() == pinned || j == pinned) it.valueRef() = it.row() == j ? 1.0 : 0.0;
    s.b(pinned) = 0;
  }
  SolveOptions pinned_options = options;
  Eigen::VectorXd guess;
  if (zero_mean && options.initial_guess != nullptr && options.initial_guess->size() == s.b.size()) {
    // The pinned system's solution is the one of zero value at the pinned coefficient: so is
    // the guess, moved by a constant.
    guess = *options.initial_guess - ((*options.initial_guess)(pinned) / constant(pinned)) * constant;
    pinned_options.initial_guess = &guess;
  }
  Solution sol = solve_linear_system(s.a, s.b, detail::loop_solver(pinned_options, s.a), problem.name);
  sol.assembly_seconds = s.seconds;
  sol.zero_mean = zero_mean;
  if (zero_mean) sol.u -= (s.area.dot(sol.u) / s.area.dot(constant)) * constant;
  return sol;
}

Solution solve_loop_biharmonic(const LoopSpace& space, const BiharmonicProblem& problem,
                               const SolveOptions& options) {
  require_closed(space, problem.name);
  detail::require_smooth(space, problem.name);
  if (!(problem.c > 0) || !std::isfinite(problem.c))
    throw InputError("problem '" + problem.name +
                     "': the coefficient c must be finite and > 0 (with c = 0 the "
                     "solution on a closed surface is defined up to a constant)");
  if (!problem.source) throw InputError("problem '" + problem.name + "' has no source");
  detail::LoopSystem s = assemble_loop(space, {true, problem.c, problem.source}, PointSource(), problem.name);
  Solution sol = solve_linear_system(s.a, s.b, detail::loop_solver(options, s.a), problem.name);
  sol.assembly_seconds = s.seconds;
  return sol;
}

}  // namespace rgbmesh::fem
