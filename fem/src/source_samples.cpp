#include "source_samples.hpp"

#include <limits>
#include <tuple>
#include <type_traits>

#include "for_each_index.hpp"

namespace rgbmesh::fem::detail {

std::vector<double> point_values(const PointValues& field, const std::vector<Vec3>& points) {
  // NaN where the field writes nothing: the solver then refuses the data as not finite.
  std::vector<double> values(points.size(), std::numeric_limits<double>::quiet_NaN());
  if (!points.empty()) field(points.data(), points.size(), values.data());
  return values;
}

SourceSamples::SourceSamples(const SurfaceMesh& mesh, const Problem& problem, SamplePoints where,
                             const WorkShare& share) {
  if (problem.source && problem.source_values)
    throw InputError("problem '" + problem.name + "': both source and source_values are set (give one)");
  if (problem.source) {
    pointwise_ = &problem.source;
    return;
  }
  if (!problem.source_values) return;
  const std::size_t nt = mesh.triangles.size();
  const auto& rule = triangle_quadrature();
  static_assert(std::tuple_size<std::decay_t<decltype(rule)>>::value == kPoints, "kPoints is the rule's size");
  // (P1 elements are the flat triangles, and the computations take their points so.)
  const bool flat = where == SamplePoints::flat || mesh.order == 1;
  // The points of the computed triangles, in triangle order, on every core.
  std::vector<std::size_t> first(nt + 1, 0);
  for (std::size_t t = 0; t < nt; ++t) first[t + 1] = first[t] + (share.computes(t) ? kPoints : 0);
  std::vector<Vec3> points(first[nt]);
  for_each_index(nt, [&](std::size_t t) {
    if (first[t + 1] == first[t]) return;
    const auto& c = mesh.triangles[t];
    for (std::size_t q = 0; q < kPoints; ++q) {
      const auto& l = rule[q].barycentric;
      const Vec3 x = flat
                         ? l[0] * mesh.points[c[0]] + l[1] * mesh.points[c[1]] + l[2] * mesh.points[c[2]]
                         : element_point(mesh, t, l).x;
      points[first[t] + q] = mesh.lift(x);
    }
  });
  const std::vector<double> values = point_values(problem.source_values, points);
  table_.assign(kPoints * nt, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t k = first[t]; k < first[t + 1]; ++k) table_[kPoints * t + (k - first[t])] = values[k];
}

}  // namespace rgbmesh::fem::detail
