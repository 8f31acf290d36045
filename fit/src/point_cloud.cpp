// Point-cloud measures (see point_cloud.hpp): CGAL's kd-tree for the neighbours, Eigen for the
// neighbourhoods' covariance.

#include "point_cloud.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace rgbmesh::fit::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using NeighbourSearch = CGAL::Orthogonal_k_neighbor_search<CGAL::Search_traits_3<Kernel>>;

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The spread of points about the quadric height field that fits them best over their own
// principal plane: a plane alone would count curvature as noise (coarse meshes' vertices have
// neighbourhoods as curved as a noisy scan is thick). Degrees of freedom are accounted for, so
// that noise-free points on a quadric measure 0.
double residual_of_quadric(const std::vector<Eigen::Vector3d>& near) {
  constexpr int terms = 6;  // 1, u, v, u², uv, v²
  if (near.size() <= static_cast<std::size_t>(terms)) return 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& q : near) mean += q;
  mean /= static_cast<double>(near.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& q : near) covariance += (q - mean) * (q - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Matrix3d frame = eigen.eigenvectors();  // columns: normal first (smallest eigenvalue)
  Eigen::MatrixXd design(near.size(), terms);
  Eigen::VectorXd height(near.size());
  for (std::size_t i = 0; i < near.size(); ++i) {
    const Eigen::Vector3d local = frame.transpose() * (near[i] - mean);
    const double u = local(1), v = local(2);
    design.row(static_cast<Eigen::Index>(i)) << 1, u, v, u * u, u * v, v * v;
    height(static_cast<Eigen::Index>(i)) = local(0);
  }
  const Eigen::VectorXd coefficients = design.colPivHouseholderQr().solve(height);
  const double squared_residuals = (design * coefficients - height).squaredNorm();
  return std::sqrt(squared_residuals / static_cast<double>(near.size() - terms));
}

// Indices into the point vector, searched through a property map: the tree reports which point
// is near, not only where.
using IndexedPoints = std::vector<Kernel::Point_3>;
using IndexMap = CGAL::Pointer_property_map<Kernel::Point_3>::const_type;
using IndexTraits = CGAL::Search_traits_adapter<std::size_t, IndexMap, CGAL::Search_traits_3<Kernel>>;
using IndexSearch = CGAL::Orthogonal_k_neighbor_search<IndexTraits>;

}  // namespace

struct PointIndex::Tree {
  IndexedPoints points;
  std::unique_ptr<IndexSearch::Tree> tree;
};

PointIndex::PointIndex(const std::vector<Vec3>& points) : tree_(std::make_unique<Tree>()) {
  tree_->points.reserve(points.size());
  for (const Vec3& p : points) tree_->points.emplace_back(p.x, p.y, p.z);
  std::vector<std::size_t> ids(points.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  tree_->tree = std::make_unique<IndexSearch::Tree>(
      ids.begin(), ids.end(), IndexSearch::Tree::Splitter(),
      IndexTraits(CGAL::make_property_map(std::as_const(tree_->points))));
  tree_->tree->build();  // built now, so that const queries from several threads do not race
}

PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

std::size_t PointIndex::size() const { return tree_->points.size(); }

void PointIndex::nearest(const Vec3& query, std::size_t k, std::vector<std::pair<std::size_t, double>>& out) const {
  out.clear();
  if (tree_->points.empty() || k == 0) return;
  const IndexSearch search(*tree_->tree, Kernel::Point_3(query.x, query.y, query.z),
                           static_cast<unsigned>(std::min(k, tree_->points.size())), 0, true,
                           IndexSearch::Distance(CGAL::make_property_map(std::as_const(tree_->points))));
  for (const auto& [id, squared] : search) out.emplace_back(id, std::sqrt(squared));
}

std::pair<std::size_t, double> PointIndex::nearest(const Vec3& query) const {
  std::vector<std::pair<std::size_t, double>> one;
  nearest(query, 1, one);
  return one.empty() ? std::pair<std::size_t, double>(0, INFINITY) : one.front();
}

std::vector<double> local_spacing(const std::vector<Vec3>& points, const PointIndex& index) {
  std::vector<double> spacing(points.size(), 0.0);
  std::vector<std::pair<std::size_t, double>> near;
  for (std::size_t i = 0; i < points.size(); ++i) {
    index.nearest(points[i], 7, near);
    double sum = 0;
    int counted = 0;
    for (const auto& [j, d] : near) {
      if (j == i) continue;
      sum += d;
      ++counted;
    }
    spacing[i] = counted > 0 ? sum / counted : 0.0;
  }
  return spacing;
}

std::vector<double> support_spacing(std::vector<double> spacing) {
  if (spacing.empty()) return spacing;
  const double cap = 2 * median(spacing);
  for (double& s : spacing) s = std::min(s, cap);
  return spacing;
}

CloudScale measure_scale(const std::vector<Vec3>& points, int neighbours) {
  CloudScale scale;
  if (points.size() < 2) return scale;
  std::vector<Kernel::Point_3> cgal_points;
  cgal_points.reserve(points.size());
  for (const Vec3& p : points) cgal_points.emplace_back(p.x, p.y, p.z);
  const NeighbourSearch::Tree tree(cgal_points.begin(), cgal_points.end());
  const auto k =
      static_cast<unsigned>(std::min<std::size_t>(static_cast<std::size_t>(neighbours) + 1, points.size()));
  std::vector<double> spacing, noise;
  spacing.reserve(points.size());
  noise.reserve(points.size());
  std::vector<Eigen::Vector3d> near;
  for (const Kernel::Point_3& p : cgal_points) {
    near.clear();
    double sum = 0;
    int counted = 0;
    for (const auto& [q, squared_distance] : NeighbourSearch(tree, p, k)) {
      near.emplace_back(q.x(), q.y(), q.z());
      if (squared_distance > 0 && counted < 6) {  // the point itself is not its own neighbour
        sum += std::sqrt(squared_distance);
        ++counted;
      }
    }
    if (counted > 0) spacing.push_back(sum / counted);
    noise.push_back(residual_of_quadric(near));
  }
  if (!spacing.empty()) scale.spacing = median(std::move(spacing));
  scale.noise = median(std::move(noise));
  return scale;
}

double denoising_cell(const CloudScale& scale, double noisy_above) {
  if (!(noisy_above > 0) || !(scale.spacing > 0) || scale.noise <= noisy_above * scale.spacing) return 0;
  return scale.spacing * std::sqrt(scale.noise / scale.spacing / (noisy_above / 3));
}

std::vector<Vec3> cell_means(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, double h,
                             std::vector<Vec3>& mean_normals) {
  struct Cluster {
    Vec3 position_sum, normal_sum;
    int count = 0;
  };
  Vec3 low = points.front();
  for (const Vec3& p : points) low = Vec3(std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z));
  const auto cell_key = [&](const Vec3& p) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a)  // 21 bits per axis: two million cells along the longest side
      key = key << 21 | (static_cast<std::uint64_t>((p[a] - low[a]) / h) & 0x1FFFFF);
    return key;
  };
  std::vector<Cluster> clusters;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> clusters_in_cell;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::size_t>& in_cell = clusters_in_cell[cell_key(points[i])];
    std::size_t c = in_cell.empty() ? clusters.size() : in_cell.front();
    if (!normals.empty()) {
      const auto same_side = std::find_if(in_cell.begin(), in_cell.end(), [&](std::size_t other) {
        return dot(clusters[other].normal_sum, normals[i]) > 0;
      });
      c = same_side == in_cell.end() ? clusters.size() : *same_side;
    }
    if (c == clusters.size()) {
      clusters.emplace_back();
      in_cell.push_back(c);
    }
    clusters[c].position_sum += points[i];
    if (!normals.empty()) clusters[c].normal_sum += normals[i];
    ++clusters[c].count;
  }
  std::vector<Vec3> means;
  means.reserve(clusters.size());
  mean_normals.clear();
  for (const Cluster& c : clusters) {
    means.push_back(c.position_sum * (1.0 / c.count));
    if (!normals.empty()) mean_normals.push_back(c.normal_sum * (1.0 / norm(c.normal_sum)));
  }
  return means;
}

}  // namespace rgbmesh::fit::detail
