#include "rgbmesh/fit/fit.hpp"

#include <ceres/ceres.h>
#include <vtkCellArray.h>
#include <vtkGenericCell.h>
#include <vtkIdList.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>
#include <vtkStaticPointLocator.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::fit {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

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

// The limit surface as VTK data, for the locators.
vtkSmartPointer<vtkPolyData> polydata(const std::vector<Vec3>& points,
                                      const std::vector<std::array<std::int32_t, 3>>& triangles) {
  auto pts = vtkSmartPointer<vtkPoints>::New();
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) pts->SetPoint(static_cast<vtkIdType>(i), points[i].x, points[i].y, points[i].z);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& t : triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  if (!triangles.empty()) pd->SetPolys(cells);
  return pd;
}

struct Footpoint {
  std::int32_t triangle;
  std::array<double, 3> barycentric;
  Vec3 normal;
  double distance;
};

// Closest points of the targets on the triangle mesh (limit positions at the refined level).
std::vector<Footpoint> footpoints(const std::vector<Vec3>& surface, const std::vector<std::array<std::int32_t, 3>>& tris,
                                  const std::vector<Vec3>& targets) {
  auto pd = polydata(surface, tris);
  auto locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  locator->SetDataSet(pd);
  locator->BuildLocator();
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  std::vector<Footpoint> out(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    double q[3] = {targets[i].x, targets[i].y, targets[i].z}, c[3];
    vtkIdType id = -1;
    int sub = 0;
    double d2 = 0;
    locator->FindClosestPoint(q, c, cell, id, sub, d2);
    const auto& t = tris[static_cast<std::size_t>(id)];
    const Vec3 a = surface[t[0]], b = surface[t[1]], d = surface[t[2]], p(c[0], c[1], c[2]);
    // Barycentric coordinates of the closest point.
    const Vec3 n = cross(b - a, d - a);
    const double area2 = dot(n, n);
    const double l1 = dot(cross(d - p, a - p), n) / area2, l2 = dot(cross(a - p, b - p), n) / area2;
    out[i] = {static_cast<std::int32_t>(id), {1 - l1 - l2, l1, l2}, n * (1.0 / std::sqrt(area2)), std::sqrt(d2)};
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

LimitStencils limit_stencils(const TriangleMeshData& base, int level) {
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
  RgbMesh real = RgbMesh::from_triangles(base.points, base.triangles);
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
    std::vector<Vec3> probe(base.points.size());
    for (std::int32_t j = 0; j < n; ++j) {
      const int c = colour[j] - 3 * r;
      probe[j] = Vec3(c == 0, c == 1, c == 2);
    }
    RgbMesh m = RgbMesh::from_triangles(probe, base.triangles);
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

FitResult fit(const TriangleMeshData& base, const std::vector<Vec3>& targets, const FitOptions& options,
              const std::function<void(const IterationReport&)>& on_iteration) {
  if (targets.empty()) throw InputError("fit: no target points");
  const auto t_start = std::chrono::steady_clock::now();
  FitResult res;
  res.diagonal = bounding_box_diagonal(targets);
  res.stencils = limit_stencils(base, options.levels);
  const LimitStencils& st = res.stencils;
  const auto adj = adjacency(base);
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
  auto measure = [&](const std::vector<Footpoint>& fp, int iteration, std::chrono::steady_clock::time_point t0) {
    IterationReport r;
    r.iteration = iteration;
    double sum = 0;
    for (const auto& f : fp) {
      sum += f.distance * f.distance;
      r.max = std::max(r.max, f.distance);
    }
    r.rms = std::sqrt(sum / static_cast<double>(fp.size()));
    r.seconds = seconds_since(t0);
    res.iterations.push_back(r);
    if (on_iteration) on_iteration(r);
    return r;
  };

  auto t0 = std::chrono::steady_clock::now();
  std::vector<Vec3> surface = st.evaluate(control_points());
  std::vector<Footpoint> fp = footpoints(surface, st.triangles, targets);
  IterationReport last = measure(fp, 0, t0), best = last;
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
  const double smooth = options.smooth * static_cast<double>(targets.size()) / static_cast<double>(base.points.size());
  for (int it = 1; it <= options.max_iterations; ++it) {
    t0 = std::chrono::steady_clock::now();
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (std::size_t j = 0; j < base.points.size(); ++j) problem.AddParameterBlock(&x[3 * j], 3);
    // The tangential part steadies the first iterations and fades out, so that the last ones
    // are point-to-plane (which converges fast once the correspondences are right).
    const double tangential = options.tangential_weight * std::pow(0.5, it - 1);
    std::map<std::int32_t, double> coeff;
    for (std::size_t i = 0; i < targets.size(); ++i) {
      const Footpoint& f = fp[i];
      coeff.clear();
      const auto& t = st.triangles[static_cast<std::size_t>(f.triangle)];
      for (int k = 0; k < 3; ++k) {
        for (std::int32_t s = st.offset[t[k]]; s < st.offset[t[k] + 1]; ++s) coeff[st.index[s]] += f.barycentric[k] * st.weight[s];
      }
      std::vector<double> c;
      std::vector<double*> blocks;
      for (const auto& [j, w] : coeff) {
        c.push_back(w);
        blocks.push_back(&x[3 * static_cast<std::size_t>(j)]);
      }
      ceres::LossFunction* loss = nullptr;
      if (options.loss == Loss::huber) loss = new ceres::HuberLoss(scale);
      if (options.loss == Loss::cauchy) loss = new ceres::CauchyLoss(scale);
      problem.AddResidualBlock(new PointToPlane(std::move(c), f.normal, targets[i], tangential), loss, blocks);
    }
    if (smooth > 0) {
      for (std::size_t j = 0; j < base.points.size(); ++j) {
        if (adj[j].empty()) continue;
        std::vector<double*> blocks = {&x[3 * j]};
        for (std::int32_t k : adj[j]) blocks.push_back(&x[3 * static_cast<std::size_t>(k)]);
        problem.AddResidualBlock(new Umbrella(static_cast<int>(adj[j].size()), smooth), nullptr, blocks);
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
    surface = st.evaluate(control_points());
    fp = footpoints(surface, st.triangles, targets);
    const IterationReport r = measure(fp, it, t0);
    const bool stalled = last.rms - r.rms < options.min_improvement * last.rms;
    if (r.rms < best.rms) {
      best = r;
      best_x = x;
    }
    last = r;
    if (stalled) break;
  }
  // The best iterate (a last step may overshoot).
  x = best_x;
  surface = st.evaluate(control_points());
  res.control_points = control_points();
  res.rms = best.rms;
  res.max = best.max;
  // Per limit vertex: the distance to the nearest target.
  auto cloud = polydata(targets, {});
  auto locator = vtkSmartPointer<vtkStaticPointLocator>::New();
  locator->SetDataSet(cloud);
  locator->BuildLocator();
  res.distance.resize(surface.size());
  for (std::size_t v = 0; v < surface.size(); ++v) {
    double p[3] = {surface[v].x, surface[v].y, surface[v].z};
    const vtkIdType id = locator->FindClosestPoint(p);
    res.distance[v] = distance(surface[v], targets[static_cast<std::size_t>(id)]);
  }
  res.seconds = seconds_since(t_start);
  return res;
}

std::vector<Vec3> read_points(const std::string& path) {
  std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".xyz") {
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot be opened");
    std::vector<Vec3> out;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream s(line);
      Vec3 p;
      if (!(s >> p.x >> p.y >> p.z)) throw InputError(path + ":" + std::to_string(n) + ": expected three numbers");
      if (!is_finite(p)) throw InputError(path + ":" + std::to_string(n) + ": non-finite coordinate");
      out.push_back(p);
    }
    if (out.empty()) throw InputError(path + ": no points");
    return out;
  }
  if (ext == ".vtp") {
    // A point cloud in VTK's format usually carries vertex cells, which mesh reading rejects:
    // take the points and ignore the cells.
    auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    if (!reader->CanReadFile(path.c_str())) throw InputError(path + ": not a readable VTK XML PolyData file");
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkPolyData* pd = reader->GetOutput();
    std::vector<Vec3> out;
    for (vtkIdType i = 0; pd != nullptr && i < pd->GetNumberOfPoints(); ++i) {
      double p[3];
      pd->GetPoint(i, p);
      out.emplace_back(p[0], p[1], p[2]);
      if (!is_finite(out.back())) throw InputError(path + ": point " + std::to_string(i) + " is not finite");
    }
    if (out.empty()) throw InputError(path + ": no points");
    return out;
  }
  const PolygonSoup soup = read_polygon_soup(path);
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    if (!is_finite(soup.points[i])) throw InputError(path + ": point " + std::to_string(i) + " is not finite");
  }
  if (soup.points.empty()) throw InputError(path + ": no points");
  return soup.points;
}

TriangleMeshData decimate(const TriangleMeshData& mesh, std::size_t faces) {
  auto pd = polydata(mesh.points, mesh.triangles);
  auto dec = vtkSmartPointer<vtkQuadricDecimation>::New();
  dec->SetInputData(pd);
  dec->SetTargetReduction(1.0 - std::min(1.0, static_cast<double>(faces) / static_cast<double>(mesh.triangles.size())));
  dec->VolumePreservationOn();
  dec->Update();
  vtkPolyData* out = dec->GetOutput();
  PolygonSoup soup;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    double p[3];
    out->GetPoint(i, p);
    soup.points.emplace_back(p[0], p[1], p[2]);
  }
  auto ids = vtkSmartPointer<vtkIdList>::New();
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c) {
    out->GetCellPoints(c, ids);
    std::vector<std::int64_t> face;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) face.push_back(static_cast<std::int64_t>(ids->GetId(k)));
    soup.faces.push_back(face);
  }
  return prepare_triangle_mesh(soup);
}

}  // namespace rgbmesh::fit
