// Two-sided distances between a fitted surface and its target (see distances.hpp).

#include "rgbmesh/fit/distances.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "point_cloud.hpp"
#include "rgbmesh/fit/fit.hpp"

namespace rgbmesh::fit {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using TriangleTree = CGAL::AABB_tree<
    CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

// The i-th point of an additive recurrence in the unit square (the plastic number's, which
// spreads any number of points evenly), folded into the triangle u, v >= 0, u + v <= 1.
std::pair<double, double> triangle_pattern(std::size_t i) {
  constexpr double g = 1.32471795724474602596;  // x^3 = x + 1
  double u = std::fmod(1.0 / 3 + static_cast<double>(i) / g, 1.0);
  double v = std::fmod(1.0 / 3 + static_cast<double>(i) / (g * g), 1.0);
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  return {u, v};
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f%%", 100 * fraction);
  return text;
}

}  // namespace

std::vector<Vec3> surface_samples(const TriangleMeshData& mesh, std::size_t count) {
  std::vector<Vec3> samples = mesh.points;
  if (count <= samples.size()) return samples;
  double total = 0;
  for (const auto& t : mesh.triangles) total += triangle_area(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
  if (!(total > 0)) return samples;
  const double per_area = static_cast<double>(count - samples.size()) / total;
  // Each triangle's share rounded, the fractions carried on, so that the total is right and no
  // triangle's share is lost to rounding however small the triangles are.
  double carried = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    carried += per_area * triangle_area(a, b, c);
    const auto n = static_cast<std::size_t>(std::floor(carried));
    carried -= static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto [u, v] = n == 1 ? std::pair<double, double>(1.0 / 3, 1.0 / 3) : triangle_pattern(i);
      samples.push_back(a + u * (b - a) + v * (c - a));
    }
  }
  return samples;
}

std::size_t target_sample_count(std::size_t target_vertices, std::size_t base_faces, int levels) {
  // A quarter of the limit surface's triangles: the surface-to-target terms hold every limit
  // vertex to the target already, and four times as many samples changed the fits of CGAL's
  // fandisk and pinion by under 3% of their distances for 2.7 times the time.
  const double limit_triangles = static_cast<double>(base_faces) * std::pow(4.0, levels);
  return std::max(target_vertices, static_cast<std::size_t>(std::min(limit_triangles / 4, 250000.0)));
}

struct TargetSurface::Impl {
  // A mesh target.
  std::vector<Triangle> triangles;
  std::unique_ptr<TriangleTree> tree;
  // A cloud target: its points, each with a tangent plane (normal to the least spread of its 8
  // nearest) and a footprint (its local spacing).
  std::vector<Vec3> points, normals;
  std::vector<double> footprint;
  std::unique_ptr<detail::PointIndex> index;

  TargetSurface::Closest mesh_closest(const Vec3& q) const {
    const auto [p, primitive] = tree->closest_point_and_primitive(Kernel::Point_3(q.x, q.y, q.z));
    const Kernel::Vector_3 n = primitive->supporting_plane().orthogonal_vector();
    const Vec3 normal(n.x(), n.y(), n.z()), at(p.x(), p.y(), p.z());
    return {at, normal * (1.0 / norm(normal)), distance(q, at)};
  }

  void prepare_cloud() {
    index = std::make_unique<detail::PointIndex>(points);
    footprint = detail::local_spacing(points, *index);
    normals.resize(points.size());
    std::vector<std::pair<std::size_t, double>> near;
    for (std::size_t i = 0; i < points.size(); ++i) {
      index->nearest(points[i], 8, near);
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto& [j, d] : near) centroid += Eigen::Vector3d(points[j].x, points[j].y, points[j].z);
      centroid /= static_cast<double>(near.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const auto& [j, d] : near) {
        const Eigen::Vector3d r = Eigen::Vector3d(points[j].x, points[j].y, points[j].z) - centroid;
        covariance += r * r.transpose();
      }
      const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(0);
      normals[i] = Vec3(n.x(), n.y(), n.z());
    }
  }

  // The nearest of the 4 nearest points' tangent discs: across the plane, plus however far the
  // query lies beyond the disc. Each point's own plane, not one plane through several: along a
  // sharp crease of a CAD cloud one plane through points of both sides lies off both.
  TargetSurface::Closest cloud_closest(const Vec3& q, std::vector<std::pair<std::size_t, double>>& near) const {
    index->nearest(q, 4, near);
    TargetSurface::Closest best;
    best.distance = INFINITY;
    for (const auto& [j, d] : near) {
      const Vec3 offset = q - points[j];
      const double across = dot(offset, normals[j]);
      const Vec3 tangential = offset - across * normals[j];
      const double along = norm(tangential);
      const double beyond = std::max(0.0, along - footprint[j]);
      const double dist = std::sqrt(across * across + beyond * beyond);
      if (dist < best.distance) {
        const Vec3 rim = beyond > 0 ? tangential * (footprint[j] / along) : tangential;
        best = {points[j] + rim, normals[j], dist};
      }
    }
    return best;
  }
};

TargetSurface::TargetSurface(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
TargetSurface::TargetSurface(TargetSurface&&) noexcept = default;
TargetSurface& TargetSurface::operator=(TargetSurface&&) noexcept = default;
TargetSurface::~TargetSurface() = default;

TargetSurface TargetSurface::from_mesh(const TriangleMeshData& mesh) {
  auto impl = std::make_unique<Impl>();
  const auto point = [](const Vec3& p) { return Kernel::Point_3(p.x, p.y, p.z); };
  impl->triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    impl->triangles.emplace_back(point(mesh.points[t[0]]), point(mesh.points[t[1]]), point(mesh.points[t[2]]));
  impl->tree = std::make_unique<TriangleTree>(impl->triangles.begin(), impl->triangles.end());
  impl->tree->accelerate_distance_queries();
  return TargetSurface(std::move(impl));
}

TargetSurface TargetSurface::from_points(const std::vector<Vec3>& points) {
  auto impl = std::make_unique<Impl>();
  impl->points = points;
  impl->prepare_cloud();
  return TargetSurface(std::move(impl));
}

bool TargetSurface::is_mesh() const { return impl_->tree != nullptr; }

std::vector<TargetSurface::Closest> TargetSurface::closest(const std::vector<Vec3>& queries,
                                                           const StageControl& control) const {
  std::vector<Closest> out(queries.size());
  std::vector<std::pair<std::size_t, double>> near;
  const std::string stage = "measuring the distances from the surface to the target";
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (i % 16384 == 0) control.step(stage, static_cast<double>(i) / static_cast<double>(queries.size()));
    out[i] = is_mesh() ? impl_->mesh_closest(queries[i]) : impl_->cloud_closest(queries[i], near);
  }
  return out;
}

std::vector<double> TargetSurface::distances(const std::vector<Vec3>& queries, const StageControl& control) const {
  const std::vector<Closest> c = closest(queries, control);
  std::vector<double> out(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) out[i] = c[i].distance;
  return out;
}

TwoSidedDistances two_sided_distances(const FitResult& result, const TargetSurface& target,
                                      const StageControl& control) {
  TwoSidedDistances d;
  d.diagonal = result.diagonal;
  d.noisy_targets = result.noisy_targets;
  d.to_surface_rms = result.rms;
  d.to_surface_max = result.max;
  if (!result.distance.empty()) {
    std::vector<double> sorted = result.distance;
    const auto k = static_cast<std::size_t>(0.99 * static_cast<double>(sorted.size() - 1));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    d.to_surface_p99 = sorted[k];
  }
  const std::vector<Vec3> surface = result.stencils.evaluate(result.control_points);
  std::vector<double> weight(surface.size(), 0.0);
  for (const auto& t : result.stencils.triangles) {
    const double third = triangle_area(surface[t[0]], surface[t[1]], surface[t[2]]) / 3;
    for (const std::int32_t v : t) weight[v] += third;
  }
  d.to_target = target.distances(surface, control);
  double sum = 0, total = 0;
  for (std::size_t v = 0; v < surface.size(); ++v) {
    sum += weight[v] * d.to_target[v] * d.to_target[v];
    total += weight[v];
    d.to_target_max = std::max(d.to_target_max, d.to_target[v]);
  }
  d.to_target_rms = total > 0 ? std::sqrt(sum / total) : 0.0;
  return d;
}

Verdict judge(const TwoSidedDistances& d, const AcceptanceRule& rule) {
  Verdict v;
  const double noise = d.noisy_targets ? 1.0 : 0.0;
  const double rms_allowed = std::max(rule.rms * d.diagonal, noise * rule.rms_ratio * d.to_surface_rms);
  const double max_allowed = std::max(rule.max * d.diagonal, noise * rule.max_ratio * d.to_surface_p99);
  const auto relative = [&](double x) { return percent(x / d.diagonal); };
  if (d.to_surface_p99 > rule.targets_p99 * d.diagonal)
    v.reason = "the fitted surface does not reach the targets: a hundredth of them lie farther than " +
               relative(d.to_surface_p99) + " of the diagonal from it (at most " + percent(rule.targets_p99) +
               " is accepted; targets-to-surface RMS " + relative(d.to_surface_rms) +
               "): parts of the target that the base does not cover, or many outliers";
  else if (d.to_target_rms > rms_allowed)
    v.reason = "the fitted surface is far from the target: surface-to-target RMS " + relative(d.to_target_rms) +
               " of the diagonal, against " + relative(d.to_surface_rms) + " from the targets to the surface (at most " +
               relative(rms_allowed) + " is accepted)";
  else if (d.to_target_max > max_allowed)
    v.reason = "part of the fitted surface is far from the target: surface-to-target max " +
               relative(d.to_target_max) + " of the diagonal (at most " + relative(max_allowed) +
               " is accepted; the targets' 99th percentile to the surface is " + relative(d.to_surface_p99) + ")";
  v.accepted = v.reason.empty();
  return v;
}

}  // namespace rgbmesh::fit
