#pragma once
/// \file
/// Fitting a Loop subdivision surface to scanned points: the base mesh's control points move so
/// that the limit surface passes through the targets (point-to-plane distances at footpoints,
/// a robust loss, a smoothness term on the control net; solved with Ceres).

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/control.hpp"
#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::fit {

/// The limit surface of a base mesh after `level` uniform RGB refinements, as a triangle mesh
/// whose vertices are the limit positions, each a sparse linear combination of base control
/// points: limit(v) = Σ_k weight[k] * base[index[k]] over v's stencil.
struct LimitStencils {
  std::vector<std::array<std::int32_t, 3>> triangles;  ///< over the refined vertices
  std::vector<std::int32_t> offset;                    ///< stencil of vertex v: [offset[v], offset[v+1])
  std::vector<std::int32_t> index;                     ///< base vertex
  std::vector<double> weight;
  std::size_t num_vertices() const { return offset.empty() ? 0 : offset.size() - 1; }
  /// The limit positions for the given base control points.
  std::vector<Vec3> evaluate(const std::vector<Vec3>& base) const;
};

/// Computes the stencils by linearity: the geometry of RGB subdivision is linear in the base
/// points, so refining probe meshes whose base coordinates are indicator functions of colour
/// classes (base vertices farther apart than any stencil's reach) reveals every weight; three
/// classes per run, one per coordinate. Checked against a refinement with the real base points.
LimitStencils limit_stencils(const TriangleMeshData& base, int level, const StageControl& control = {});

enum class Loss { none, huber, cauchy };

struct FitOptions {
  int levels = 3;          ///< uniform refinement of the base for the limit surface
  Loss loss = Loss::huber;
  double loss_scale = 0;   ///< 0: from the data (2.5 robust standard deviations of the distances)
  double smooth = 1e-3;    ///< weight of the control-net Laplacian, relative (see fit())
  double tangential_weight = 0.05;  ///< of the tangential offset next to the normal one
  int max_iterations = 30;
  int ceres_iterations = 2;  ///< per outer iteration (the problem is nearly linear)
  double min_improvement = 2e-2;  ///< stop when the RMS improves by less (relative)
  /// Targets whose noise (measured about local quadric fits) is above this fraction r of their
  /// spacing get `smooth` multiplied by (noise / (r/2 spacing))², at least 4 (see fit.cpp); 0:
  /// never.
  double noisy_above = 0.3;
  /// Weight of the surface-to-target terms, when fit() is given the target's surface: 1 weighs
  /// the surface's area like the targets (see fit()).
  double surface_weight = 1;
};

struct IterationReport {
  int iteration = 0;
  double rms = 0, max = 0;  ///< distances from the targets to the limit surface
  /// From the limit surface to the target's surface (area-weighted RMS over the limit
  /// vertices), when fit() was given it; 0 otherwise.
  double surface_rms = 0;
  double seconds = 0;
};

struct FitResult {
  std::vector<Vec3> control_points;  ///< the fitted base
  std::vector<IterationReport> iterations;  ///< iteration 0: the start
  double rms = 0, max = 0;                  ///< final: over `distance`, every target
  double diagonal = 0;                      ///< of the targets' bounding box
  double seconds = 0;
  LimitStencils stencils;
  /// Per target, for the fitted surface: the distance to the limit surface (at stencils' level)
  /// and the limit-surface triangle (in stencils.triangles) that holds the closest point.
  std::vector<double> distance;
  std::vector<std::int32_t> footpoint_triangle;
  double smooth = 0;               ///< the smoothness weight used (options.smooth, raised for noise)
  /// The targets' noise measured against their spacing (options.noisy_above), and whether it
  /// is above it: such targets are a thick shell that no smooth surface comes nearer than.
  double noise_to_spacing = 0;
  bool noisy_targets = false;
  std::vector<std::string> notes;  ///< e.g. that noisy targets got more smoothing
};

/// About how many bytes fit() takes at most for `targets` points and a base of `base_faces`
/// triangles at `levels` (and the surface-to-target terms): the Ceres problem holds about
/// 3.5 kB per residual (measured: 395 MB for 64,000 targets and 32,000 limit vertices), the
/// stencils and footpoint trees much less. For refusing a fit up front, not for accounting.
double estimated_fit_bytes(std::size_t targets, std::size_t base_faces, int levels);

/// Per limit-surface triangle: how many targets have their closest point in it, and the RMS of
/// their distances (0 where there are none). What the fitted surface's error looks like where it
/// is, instead of the spacing of the samples.
struct TriangleDistances {
  std::vector<double> targets;
  std::vector<double> rms_distance;
};
TriangleDistances distances_per_triangle(const FitResult& result);

/// Fits the base mesh (its points are the starting control points) to the target points.
/// Each outer iteration finds every target's closest point on the current limit surface (a
/// cell locator), then minimises Σ ρ((n·(s(P) - q))² + ε |tangential part of s(P) - q|²) +
/// smooth · (\#targets / \#base) Σ_j |P_j - mean of P_j's neighbours|² over the control points
/// P, where s(P) is the footpoint (linear in P through the stencils), n the surface normal
/// there, ε = tangential_weight and ρ the loss (point-to-plane after Marinov and Kobbelt, with
/// a little point-to-point for stability). Noisy targets (options.noisy_above) get a larger
/// smoothness weight.
/// `control` is called between iterations and within long steps (StageControl).
///
/// With `target_surface` (the surface the targets sample: a mesh target's triangles, a cloud's
/// points as discs, see distances.hpp) the fit is two-sided: each limit vertex v also adds
/// surface_weight · \#targets · (its share of the limit surface's area) · ρ(|s_v(P) - c_v|²), c_v
/// its nearest point on the target, so that no part of the surface is free to go where no
/// target is (point-to-surface fitting alone is blind to it). The iterations then stop on the
/// combined RMS of both directions.
FitResult fit(const TriangleMeshData& base, const std::vector<Vec3>& targets, const FitOptions& options,
              const std::function<void(const IterationReport&)>& on_iteration = {},
              const StageControl& control = {}, const TargetSurface* target_surface = nullptr);

}  // namespace rgbmesh::fit
