#pragma once
/// \file
/// How far a fitted surface is from its target, in both directions, and whether that is a fit
/// to report as one.
///
/// The fit minimises the distances from the targets to the limit surface. That direction alone
/// misses where the surface goes that no target is: between the vertices of a coarse CAD mesh
/// (the surface passes through them and bulges between), around a sparse cloud, across the
/// open side of a scan. The other direction, from the fitted surface to the target, sees it.
/// A mesh target is measured as the surface its triangles make; a cloud as the surface its
/// points sample (below).

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rgbmesh/fit/control.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fit {

struct FitResult;

/// Points for fitting a mesh target as the surface it is: its vertices (first, in order), then
/// points spread over its triangles in proportion to their areas, about `count` in all (never
/// fewer than the vertices), on a fixed low-discrepancy pattern in each triangle (the same
/// points in every run).
std::vector<Vec3> surface_samples(const TriangleMeshData& mesh, std::size_t count);

/// How many points surface_samples should spread over a mesh target fitted by a base of
/// `base_faces` triangles at `levels` levels: a quarter as many as the limit surface has
/// triangles (base_faces * 4^(levels - 1)), at most 250,000, and never fewer than the target's
/// vertices.
std::size_t target_sample_count(std::size_t target_vertices, std::size_t base_faces, int levels);

/// The target as a surface to measure distances to.
///  * A triangle mesh: the exact distance to its triangles (CGAL's AABB tree).
///  * A point cloud: each point stands for a small disc of the surface, in its tangent plane
///    (normal to the least spread of its 8 nearest points) with its local spacing as radius.
///    The distance is that to the nearest of the 4 nearest points' discs: across the plane,
///    plus however far the query lies beyond the disc's rim. Surface between points is not
///    charged for the sampling's gaps, and surface where no point is counts as far as it is
///    from the points.
class TargetSurface {
 public:
  static TargetSurface from_mesh(const TriangleMeshData& mesh);
  static TargetSurface from_points(const std::vector<Vec3>& points);
  TargetSurface(TargetSurface&&) noexcept;
  TargetSurface& operator=(TargetSurface&&) noexcept;
  ~TargetSurface();

  bool is_mesh() const;

  /// The nearest point of the target surface to a query (on a triangle, or on a point's disc),
  /// with the surface's unit normal there (its sign is arbitrary) and the distance.
  struct Closest {
    Vec3 point, normal;
    double distance = 0;
  };
  std::vector<Closest> closest(const std::vector<Vec3>& queries, const StageControl& control = {}) const;

  /// The distance of each query point to the target surface.
  std::vector<double> distances(const std::vector<Vec3>& queries, const StageControl& control = {}) const;

 private:
  struct Impl;
  explicit TargetSurface(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

struct TwoSidedDistances {
  double diagonal = 0;  ///< of the targets' bounding box (FitResult::diagonal)
  bool noisy_targets = false;  ///< FitResult::noisy_targets
  /// Targets to the fitted limit surface: the fit's own figures (FitResult::rms and max), and
  /// the 99th percentile, which outliers of a scan do not move.
  double to_surface_rms = 0, to_surface_max = 0, to_surface_p99 = 0;
  /// The fitted limit surface (its vertices at the fit's level) to the target: per vertex, the
  /// RMS weighted by the vertices' areas (a third of their triangles'), and the largest.
  std::vector<double> to_target;
  double to_target_rms = 0, to_target_max = 0;
};

/// Both directions for a fit's result and its target.
TwoSidedDistances two_sided_distances(const FitResult& result, const TargetSurface& target,
                                      const StageControl& control = {});

/// When a fit is reported as one. The surface-to-target distances must stay within
/// `rms` and `max` times the diagonal; for noisy targets (TwoSidedDistances::noisy_targets)
/// within `rms_ratio` and `max_ratio` times the target-to-surface RMS and 99th percentile where
/// those are larger (a noisy scan: no smooth surface is nearer to its points than their noise,
/// and the points' own spread shows in both directions alike). And the surface must reach the targets: their 99th
/// percentile distance to it at most `targets_p99` times the diagonal (outliers, a hundredth of
/// the points, may be anywhere).
struct AcceptanceRule {
  double rms = 0.005, max = 0.03;
  double rms_ratio = 2, max_ratio = 2;
  double targets_p99 = 0.05;
};

struct Verdict {
  bool accepted = true;
  std::string reason;  ///< why not, with the figures; empty when accepted
};
Verdict judge(const TwoSidedDistances& distances, const AcceptanceRule& rule = {});

}  // namespace rgbmesh::fit
