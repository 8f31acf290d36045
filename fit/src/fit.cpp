#include "rgbmesh/fit/fit.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include "point_cloud.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/timing.hpp"

namespace rgbmesh::fit {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using TriangleTree = CGAL::AABB_tree<
    CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

std::vector<std::vector<std::int32_t>> adjacency(const TriangleMeshData& m) {
  std::vector<std::vector<std::int32_t>> adj(m.points.size());
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      adj[t[k]].push_back(t[(k + 1) % 3]);
      adj[t[(k + 1) % 3]].push_back(t[k]);
    }
  }
  for (auto& a : adj) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  return adj;
}

// The neighbours whose mean the smoothness term pulls each control point to. With sharp
// features, a crease's points are smoothed along their crease only (its two crease
// neighbours), and corners, crossings and dart ends not at all: the smoothing would round the
// very edges the creases keep.
std::vector<std::vector<std::int32_t>> smoothing_neighbours(const TriangleMeshData& m) {
  std::vector<std::vector<std::int32_t>> adj = adjacency(m);
  if (m.sharp.empty()) return adj;
  std::vector<std::vector<std::int32_t>> along(m.points.size());
  for (const SharpEdge& e : m.sharp.edges) {
    if (e.sharpness <= 0.0f) continue;
    along[static_cast<std::size_t>(e.a)].push_back(e.b);
    along[static_cast<std::size_t>(e.b)].push_back(e.a);
  }
  for (const SharpVertex& v : m.sharp.vertices)
    if (v.sharpness > 0.0f) adj[static_cast<std::size_t>(v.v)].clear();
  for (std::size_t v = 0; v < along.size(); ++v) {
    if (along[v].empty() || adj[v].empty()) continue;
    adj[v] = along[v].size() == 2 ? along[v] : std::vector<std::int32_t>();
  }
  return adj;
}

// Base vertices within `radius` edges of the seeds.
std::vector<std::int32_t> ball(const std::vector<std::vector<std::int32_t>>& adj, const std::vector<std::int32_t>& seeds,
                               int radius, std::vector<int>& mark, int stamp) {
  std::vector<std::int32_t> out = seeds, frontier = seeds;
  for (std::int32_t s : seeds) mark[s] = stamp;
  for (int r = 0; r < radius; ++r) {
    std::vector<std::int32_t> next;
    for (std::int32_t v : frontier) {
      for (std::int32_t w : adj[v]) {
        if (mark[w] == stamp) continue;
        mark[w] = stamp;
        next.push_back(w);
        out.push_back(w);
      }
    }
    frontier.swap(next);
  }
  return out;
}

struct Footpoint {
  std::int32_t triangle;
  std::array<double, 3> barycentric;
  Vec3 normal;
  double distance;
};

// Closest points of the targets on the triangle mesh (limit positions at the refined level),
// with CGAL's AABB tree. (VTK's static cell locator, used before, sorts its bins in parallel, so
// that between equally close triangles, along shared edges, it picked one or the other from run
// to run, with their different normals: the fit was not reproducible.)
std::vector<Footpoint> footpoints(const std::vector<Vec3>& surface, const std::vector<std::array<std::int32_t, 3>>& tris,
                                  const std::vector<Vec3>& targets) {
  std::vector<Triangle> triangles;
  triangles.reserve(tris.size());
  const auto point = [](const Vec3& p) { return Kernel::Point_3(p.x, p.y, p.z); };
  for (const auto& t : tris)
    triangles.emplace_back(point(surface[t[0]]), point(surface[t[1]]), point(surface[t[2]]));
  TriangleTree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  std::vector<Footpoint> out(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Kernel::Point_3 q = point(targets[i]);
    const auto [closest, primitive] = tree.closest_point_and_primitive(q);
    const auto id = static_cast<std::size_t>(primitive - triangles.begin());
    const auto& t = tris[id];
    const Vec3 a = surface[t[0]], b = surface[t[1]], d = surface[t[2]],
               p(closest.x(), closest.y(), closest.z());
    // Barycentric coordinates of the closest point.
    const Vec3 n = cross(b - a, d - a);
    const double area2 = dot(n, n);
    const double l1 = dot(cross(d - p, a - p), n) / area2, l2 = dot(cross(a - p, b - p), n) / area2;
    out[i] = {static_cast<std::int32_t>(id),
              {1 - l1 - l2, l1, l2},
              n * (1.0 / std::sqrt(area2)),
              std::sqrt(CGAL::squared_distance(q, closest))};
  }
  return out;
}

// M (Σ_j c_j P_j - q) with M = n nᵀ + sqrt(ε) (I - n nᵀ): the distance along the normal
// (point-to-plane), plus a little of the tangential offset. Pure point-to-plane lets the
// surface slide along itself (its tangential directions are nearly free); the small
// point-to-point part keeps the iteration stable, and vanishes at the solution.
class PointToPlane final : public ceres::CostFunction {
 public:
  PointToPlane(std::vector<double> coefficients, const Vec3& normal, const Vec3& target, double tangential)
      : c_(std::move(coefficients)), q_(target) {
    set_num_residuals(3);
    for (std::size_t k = 0; k < c_.size(); ++k) mutable_parameter_block_sizes()->push_back(3);
    const double n[3] = {normal.x, normal.y, normal.z}, t = std::sqrt(tangential);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) m_[a][b] = n[a] * n[b] + t * ((a == b ? 1.0 : 0.0) - n[a] * n[b]);
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    double d[3] = {-q_.x, -q_.y, -q_.z};
    for (std::size_t k = 0; k < c_.size(); ++k)
      for (int a = 0; a < 3; ++a) d[a] += c_[k] * p[k][a];
    for (int a = 0; a < 3; ++a) r[a] = m_[a][0] * d[0] + m_[a][1] * d[1] + m_[a][2] * d[2];
    if (jac != nullptr) {
      for (std::size_t k = 0; k < c_.size(); ++k) {
        if (jac[k] == nullptr) continue;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) jac[k][3 * a + b] = c_[k] * m_[a][b];
      }
    }
    return true;
  }

 private:
  std::vector<double> c_;
  Vec3 q_;
  double m_[3][3];
};

// sqrt(λ) (P_j - mean of its neighbours): the umbrella Laplacian of the control net.
class Umbrella final : public ceres::CostFunction {
 public:
  Umbrella(int neighbours, double weight) : k_(neighbours), w_(std::sqrt(weight)) {
    set_num_residuals(3);
    for (int i = 0; i <= k_; ++i) mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    for (int d = 0; d < 3; ++d) {
      double mean = 0;
      for (int i = 1; i <= k_; ++i) mean += p[i][d];
      r[d] = w_ * (p[0][d] - mean / k_);
    }
    if (jac != nullptr) {
      for (int i = 0; i <= k_; ++i) {
        if (jac[i] == nullptr) continue;
        const double v = i == 0 ? w_ : -w_ / k_;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) jac[i][3 * a + b] = a == b ? v : 0.0;
      }
    }
    return true;
  }

 private:
  int k_;
  double w_;
};

}  // namespace

std::vector<Vec3> LimitStencils::evaluate(const std::vector<Vec3>& base) const {
  std::vector<Vec3> out(num_vertices());
  for (std::size_t v = 0; v < out.size(); ++v) {
    Vec3 s;
    for (std::int32_t k = offset[v]; k < offset[v + 1]; ++k) s += weight[k] * base[index[k]];
    out[v] = s;
  }
  return out;
}

LimitStencils limit_stencils(const TriangleMeshData& base, int level, const StageControl& control) {
  const std::string stage = "limit stencils of the base at level " + std::to_string(level);
  control.step(stage, 0);
  const auto n = static_cast<std::int32_t>(base.points.size());
  const auto adj = adjacency(base);
  // Colour classes: base vertices within 5 edges of each other differ (a limit point's stencil
  // lies within 2 edges of the base edge or triangle that contains it).
  std::vector<int> colour(static_cast<std::size_t>(n), -1), mark(static_cast<std::size_t>(n), -1);
  int colours = 0;
  for (std::int32_t v = 0; v < n; ++v) {
    std::vector<char> used(static_cast<std::size_t>(colours) + 1, 0);
    for (std::int32_t w : ball(adj, {v}, 5, mark, v)) {
      if (colour[w] >= 0) used[colour[w]] = 1;
    }
    int c = 0;
    while (used[c]) ++c;
    colour[v] = c;
    colours = std::max(colours, c + 1);
  }

  // The refined topology, with the real points (also the check below).
  RgbMesh real = RgbMesh::from_triangles(base.points, base.triangles, base.sharp);
  selective_refinement(real, UniformLevel(level));
  LimitStencils st;
  std::vector<std::int32_t> index_of(static_cast<std::size_t>(real.vertex_slots()), -1);
  std::vector<VertexHandle> vertices;
  for (VertexHandle v : real.vertices()) {
    index_of[v.idx] = static_cast<std::int32_t>(vertices.size());
    vertices.push_back(v);
  }
  for (TriangleHandle t : real.triangles()) {
    const auto c = real.triangle_vertices(t);
    st.triangles.push_back({index_of[c[0].idx], index_of[c[1].idx], index_of[c[2].idx]});
  }
  // Each refined vertex's candidates: base vertices within 2 edges of the base vertices it
  // descends from (the ends of its base edge, or the corners of its base triangle).
  std::vector<std::vector<std::int32_t>> ancestors(static_cast<std::size_t>(real.vertex_slots()));
  std::vector<std::vector<std::int32_t>> candidates(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const VertexHandle v = vertices[i];
    std::vector<std::int32_t>& a = ancestors[v.idx];
    if (real.level(v) == 0) {
      a = {v.idx};
    } else {
      for (VertexHandle p : real.parents(v)) a.insert(a.end(), ancestors[p.idx].begin(), ancestors[p.idx].end());
      std::sort(a.begin(), a.end());
      a.erase(std::unique(a.begin(), a.end()), a.end());
    }
  }
  std::fill(mark.begin(), mark.end(), -1);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    candidates[i] = ball(adj, ancestors[vertices[i].idx], 2, mark, static_cast<int>(i));

  // Probe runs: coordinate d of base vertex j is 1 when colour(j) = 3 r + d.
  std::vector<std::vector<std::pair<std::int32_t, double>>> weights(vertices.size());
  for (int r = 0; 3 * r < colours; ++r) {
    control.step(stage, static_cast<double>(3 * r) / colours);
    std::vector<Vec3> probe(base.points.size());
    for (std::int32_t j = 0; j < n; ++j) {
      const int c = colour[j] - 3 * r;
      probe[j] = Vec3(c == 0, c == 1, c == 2);
    }
    // Indicator coordinates put many corners at one point: values, not a surface. The base's
    // creases and corners shape the stencils as they shape the surface.
    RgbMesh m = RgbMesh::from_triangles(probe, base.triangles, base.sharp, PointRole::values);
    selective_refinement(m, UniformLevel(level));
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const Vec3 l = m.limit_position(vertices[i]);
      for (int d = 0; d < 3; ++d) {
        if (std::abs(l[d]) < 1e-15) continue;
        const int c = 3 * r + d;
        std::int32_t found = -1;
        for (std::int32_t j : candidates[i]) {
          if (colour[j] == c) found = j;
        }
        if (found < 0) throw std::logic_error("limit_stencils: a weight outside the expected stencil");
        weights[i].emplace_back(found, l[d]);
      }
    }
  }
  st.offset.push_back(0);
  for (const auto& w : weights) {
    for (const auto& [j, x] : w) {
      st.index.push_back(j);
      st.weight.push_back(x);
    }
    st.offset.push_back(static_cast<std::int32_t>(st.index.size()));
  }
  // The check: the stencils reproduce the limit positions of the real mesh.
  const std::vector<Vec3> approx = st.evaluate(base.points);
  const double diagonal = bounding_box_diagonal(base.points);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (distance(approx[i], real.limit_position(vertices[i])) > 1e-9 * diagonal)
      throw std::logic_error("limit_stencils: the stencils do not reproduce the limit surface");
  }
  return st;
}

namespace {

// A noisy scan is a thick shell of points, inside which closest-point fitting keeps finding
// closer surfaces by wrinkling: on CGAL's sphere_20k (noise 0.61 times the spacing) the
// fitted surface's radius came to vary 6 times more than the sphere's, the RMS falling to half
// the noise. The regularisation has to grow with the noise variance: above a noise-to-spacing
// ratio r (clean scans and meshes measure at most 0.22 there: their "noise" is curvature) the
// weight is multiplied by (ratio / (r/2))², 16.5 on that sphere, where 5 was not enough and
// 10 was. Returns the factor; records the ratio (and a note when it applies) in res.
double noise_smoothing(const std::vector<Vec3>& targets, const FitOptions& options, FitResult& res) {
  double smooth_factor = 1;
  if (options.noisy_above > 0) {
    const detail::CloudScale cloud = detail::measure_scale(targets, 18);
    const double ratio = cloud.spacing > 0 ? cloud.noise / cloud.spacing : 0;
    res.noise_to_spacing = ratio;
    res.noisy_targets = ratio > options.noisy_above;
    if (ratio > options.noisy_above) {
      smooth_factor = (ratio / (options.noisy_above / 2)) * (ratio / (options.noisy_above / 2));
      char text[200];
      std::snprintf(
          text, sizeof text,
          "the targets are noisy (%.2g, %.2g times their spacing): the smoothness weight is raised %.3g "
          "times to keep the surface from wrinkling",
          cloud.noise, ratio, smooth_factor);
      res.notes.push_back(text);
    }
  }
  return smooth_factor;
}

ceres::LossFunction* make_loss(Loss loss, double scale) {
  if (loss == Loss::huber) return new ceres::HuberLoss(scale);
  if (loss == Loss::cauchy) return new ceres::CauchyLoss(scale);
  return nullptr;
}

// What one outer iteration fits: the targets to their footpoints on the limit surface, the
// limit surface back to the target surface (where it is given), and the control net's
// smoothness.
struct IterationTerms {
  const LimitStencils& st;
  const std::vector<Vec3>& targets;
  const std::vector<Footpoint>& fp;
  const std::vector<TargetSurface::Closest>& back;
  const std::vector<double>& area_share;
  const std::vector<std::vector<std::int32_t>>& adj;
};

// One outer iteration's least-squares problem on the control points x (3 per point), solved.
void solve_iteration(std::vector<double>& x, const IterationTerms& terms, const FitOptions& options, int it,
                     double scale, double smooth) {
  const LimitStencils& st = terms.st;
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const std::size_t points = x.size() / 3;
  for (std::size_t j = 0; j < points; ++j) problem.AddParameterBlock(&x[3 * j], 3);
  // The tangential part steadies the first iterations and fades out, so that the last ones
  // are point-to-plane (which converges fast once the correspondences are right).
  const double tangential = options.tangential_weight * std::pow(0.5, it - 1);
  std::map<std::int32_t, double> coeff;
  for (std::size_t i = 0; i < terms.targets.size(); ++i) {
    const Footpoint& f = terms.fp[i];
    coeff.clear();
    const auto& t = st.triangles[static_cast<std::size_t>(f.triangle)];
    for (int k = 0; k < 3; ++k) {
      for (std::int32_t s = st.offset[t[k]]; s < st.offset[t[k] + 1]; ++s)
        coeff[st.index[s]] += f.barycentric[k] * st.weight[s];
    }
    std::vector<double> c;
    std::vector<double*> blocks;
    for (const auto& [j, w] : coeff) {
      c.push_back(w);
      blocks.push_back(&x[3 * static_cast<std::size_t>(j)]);
    }
    problem.AddResidualBlock(new PointToPlane(std::move(c), f.normal, terms.targets[i], tangential),
                             make_loss(options.loss, scale), blocks);
  }
  // Surface to target: each limit vertex pulled to its nearest point of the target (point to
  // point: where the nearest point is an edge or a rim the plane alone would let the surface
  // slide off), weighted by its share of the area so that the surface counts as much as the
  // targets do. Without it, surface that no target's footpoint lands on is free: on a spool
  // the fit stretched webs across its core, 10% of the diagonal from any target.
  for (std::size_t v = 0; v < terms.back.size(); ++v) {
    const double weight =
        options.surface_weight * terms.area_share[v] * static_cast<double>(terms.targets.size());
    if (!(weight > 0)) continue;
    std::vector<double> c(st.weight.begin() + st.offset[v], st.weight.begin() + st.offset[v + 1]);
    std::vector<double*> blocks;
    for (std::int32_t s = st.offset[v]; s < st.offset[v + 1]; ++s)
      blocks.push_back(&x[3 * static_cast<std::size_t>(st.index[s])]);
    problem.AddResidualBlock(
        new PointToPlane(std::move(c), terms.back[v].normal, terms.back[v].point, 1.0),
        new ceres::ScaledLoss(make_loss(options.loss, scale), weight, ceres::TAKE_OWNERSHIP), blocks);
  }
  if (smooth > 0) {
    for (std::size_t j = 0; j < points; ++j) {
      if (terms.adj[j].empty()) continue;
      std::vector<double*> blocks = {&x[3 * j]};
      for (std::int32_t k : terms.adj[j]) blocks.push_back(&x[3 * static_cast<std::size_t>(k)]);
      problem.AddResidualBlock(new Umbrella(static_cast<int>(terms.adj[j].size()), smooth), nullptr, blocks);
    }
  }
  ceres::Solver::Options so;
  // Conjugate gradients on the normal equations: the factorization's symbolic phase (forming
  // the structure of JᵀJ for residuals that touch some twenty control points each) costs more
  // than the solve, and would be redone every outer iteration.
  so.linear_solver_type = ceres::CGNR;
  so.preconditioner_type = ceres::JACOBI;
  so.max_linear_solver_iterations = 50;
  so.max_num_iterations = options.ceres_iterations;
  so.num_threads = 2;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
}

}  // namespace

FitResult fit(const TriangleMeshData& base, const std::vector<Vec3>& targets, const FitOptions& options,
              const std::function<void(const IterationReport&)>& on_iteration, const StageControl& control,
              const TargetSurface* target_surface) {
  if (targets.empty()) throw InputError("fit: no target points");
  const auto t_start = std::chrono::steady_clock::now();
  FitResult res;
  res.diagonal = bounding_box_diagonal(targets);
  res.stencils = limit_stencils(base, options.levels, control);
  const std::string stage = "fitting " + with_thousands(base.points.size()) + " control points to " +
                            with_thousands(targets.size()) + " targets";
  const LimitStencils& st = res.stencils;
  const auto adj = smoothing_neighbours(base);
  std::vector<double> x(3 * base.points.size());
  for (std::size_t j = 0; j < base.points.size(); ++j) {
    x[3 * j] = base.points[j].x;
    x[3 * j + 1] = base.points[j].y;
    x[3 * j + 2] = base.points[j].z;
  }
  auto control_points = [&] {
    std::vector<Vec3> p(base.points.size());
    for (std::size_t j = 0; j < p.size(); ++j) p[j] = Vec3(x[3 * j], x[3 * j + 1], x[3 * j + 2]);
    return p;
  };
  // The other direction, when the target's surface is given: each limit vertex's nearest point
  // on it, and the vertex's share of the limit surface's area (a third of its triangles').
  std::vector<TargetSurface::Closest> back;
  std::vector<double> area_share;
  const auto measure_back = [&](const std::vector<Vec3>& limit) {
    if (target_surface == nullptr) return;
    back = target_surface->closest(limit, control);
    area_share.assign(limit.size(), 0.0);
    double total = 0;
    for (const auto& t : st.triangles) {
      const double third = norm(cross(limit[t[1]] - limit[t[0]], limit[t[2]] - limit[t[0]])) / 6;
      for (const std::int32_t v : t) area_share[v] += third;
      total += 3 * third;
    }
    if (total > 0)
      for (double& a : area_share) a /= total;
  };
  auto measure = [&](const std::vector<Footpoint>& fp, int iteration, std::chrono::steady_clock::time_point t0) {
    IterationReport r;
    r.iteration = iteration;
    double sum = 0;
    for (const auto& f : fp) {
      sum += f.distance * f.distance;
      r.max = std::max(r.max, f.distance);
    }
    r.rms = std::sqrt(sum / static_cast<double>(fp.size()));
    double back_sum = 0;
    for (std::size_t v = 0; v < back.size(); ++v) back_sum += area_share[v] * back[v].distance * back[v].distance;
    r.surface_rms = std::sqrt(back_sum);
    r.seconds = seconds_since(t0);
    res.iterations.push_back(r);
    if (on_iteration) on_iteration(r);
    return r;
  };

  const double smooth_factor = noise_smoothing(targets, options, res);
  res.smooth = options.smooth * smooth_factor;

  auto t0 = std::chrono::steady_clock::now();
  std::vector<Vec3> surface = st.evaluate(control_points());
  std::vector<Footpoint> fp = footpoints(surface, st.triangles, targets);
  measure_back(surface);
  IterationReport last = measure(fp, 0, t0), best = last;
  // What the iterations decrease: both directions alike when both are fitted.
  const auto objective = [](const IterationReport& r) { return std::hypot(r.rms, r.surface_rms); };
  std::vector<double> best_x = x;
  // The loss scale from the data: 2.5 robust standard deviations (1.4826 x the median distance).
  double scale = options.loss_scale;
  if (scale <= 0) {
    std::vector<double> d;
    for (const auto& f : fp) d.push_back(f.distance);
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    scale = std::max(2.5 * 1.4826 * d[d.size() / 2], 1e-9 * res.diagonal);
  }
  // Relative to the data: each control point's regularisation weighs like its share of targets.
  const double smooth =
      res.smooth * static_cast<double>(targets.size()) / static_cast<double>(base.points.size());
  for (int it = 1; it <= options.max_iterations; ++it) {
    control.step(stage, static_cast<double>(it - 1) / options.max_iterations);
    t0 = std::chrono::steady_clock::now();
    solve_iteration(x, {st, targets, fp, back, area_share, adj}, options, it, scale, smooth);
    surface = st.evaluate(control_points());
    fp = footpoints(surface, st.triangles, targets);
    measure_back(surface);
    const IterationReport r = measure(fp, it, t0);
    const bool stalled = objective(last) - objective(r) < options.min_improvement * objective(last);
    if (objective(r) < objective(best)) {
      best = r;
      best_x = x;
    }
    last = r;
    if (stalled) break;
  }
  // The best iterate (a last step may overshoot), and its distances: the figures reported are
  // computed from exactly the per-target distances returned.
  if (best_x != x) {
    x = best_x;
    fp = footpoints(st.evaluate(control_points()), st.triangles, targets);
  }
  res.control_points = control_points();
  res.distance.resize(targets.size());
  res.footpoint_triangle.resize(targets.size());
  double sum = 0;
  res.max = 0;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    res.distance[i] = fp[i].distance;
    res.footpoint_triangle[i] = fp[i].triangle;
    sum += fp[i].distance * fp[i].distance;
    res.max = std::max(res.max, fp[i].distance);
  }
  res.rms = std::sqrt(sum / static_cast<double>(targets.size()));
  res.seconds = seconds_since(t_start);
  return res;
}

double estimated_fit_bytes(std::size_t targets, std::size_t base_faces, int levels) {
  const double limit_vertices = 0.5 * static_cast<double>(base_faces) * std::pow(4.0, levels);
  return 3500.0 * (static_cast<double>(targets) + limit_vertices);
}

TriangleDistances distances_per_triangle(const FitResult& result) {
  TriangleDistances out;
  const std::size_t n = result.stencils.triangles.size();
  out.targets.assign(n, 0.0);
  out.rms_distance.assign(n, 0.0);
  for (std::size_t i = 0; i < result.distance.size(); ++i) {
    const auto t = static_cast<std::size_t>(result.footpoint_triangle[i]);
    out.targets[t] += 1;
    out.rms_distance[t] += result.distance[i] * result.distance[i];
  }
  for (std::size_t t = 0; t < n; ++t)
    if (out.targets[t] > 0) out.rms_distance[t] = std::sqrt(out.rms_distance[t] / out.targets[t]);
  return out;
}

}  // namespace rgbmesh::fit
