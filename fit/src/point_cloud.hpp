#pragma once
// Point-cloud measures shared by the reconstruction and the fit (private to rgbmesh::fit): the
// spacing and noise of a cloud, and cell averages that reduce its noise.

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fit::detail {

// Nearest-neighbour queries on a fixed set of points (CGAL's kd-tree). Queries are const and
// may run on several threads at once.
class PointIndex {
 public:
  explicit PointIndex(const std::vector<Vec3>& points);
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;

  // The k nearest points (fewer if there are fewer) as (index, distance), nearest first.
  void nearest(const Vec3& query, std::size_t k, std::vector<std::pair<std::size_t, double>>& out) const;
  // The nearest point's index and distance.
  std::pair<std::size_t, double> nearest(const Vec3& query) const;
  std::size_t size() const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// Per point: the mean distance to its 6 nearest other points (0 for a point alone).
std::vector<double> local_spacing(const std::vector<Vec3>& points, const PointIndex& index);

// Per point: the spacing within which a surface near it counts as sampled by the points, from
// their local spacings: each at most twice the median. A point on a scan's rim or on
// a lone line of points has its neighbours on one side or along the line only, and its local
// spacing grows with the gap beside it; uncapped, a surface spanning the gap counts as sampled.
std::vector<double> support_spacing(std::vector<double> local_spacing);

struct CloudScale {
  double spacing = 0;  // median over the points of the mean distance to their 6 nearest
  // Median over the points of the spread of their k nearest neighbours about the quadric that
  // fits them best (see point_cloud.cpp): the noise's standard deviation, roughly.
  double noise = 0;
};
CloudScale measure_scale(const std::vector<Vec3>& points, int neighbours);

// For points noisier than `noisy_above` times their spacing (0: never), the grid cell size whose
// averages have a third of that left, relative to their own spacing; 0 for other points.
// Averaging over cells of size h leaves noise ν s / h next to a spacing h (about (h/s)² points
// per cell, s the spacing and ν the noise), hence h = s √(ν / (s r)) for a ratio r.
double denoising_cell(const CloudScale& scale, double noisy_above);

// Means of the points over the cells of a grid of size h. With normals, the points of a cell are
// averaged separately for each orientation met (points whose normals point away from each other
// are the two sides of a thin part and must stay apart), and the mean normals are returned,
// normalized, in `mean_normals`.
std::vector<Vec3> cell_means(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, double h,
                             std::vector<Vec3>& mean_normals);

}  // namespace rgbmesh::fit::detail
