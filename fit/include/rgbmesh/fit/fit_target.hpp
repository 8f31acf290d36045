#pragma once
/// \file
/// The whole fit as the command-line tool and the Python package run it: the target taken for
/// what it is (a mesh target is the surface its triangles make; a point cloud is points), the
/// base given or built from it, the fit, and its two-sided check.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/control.hpp"
#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/fit/fit.hpp"

namespace rgbmesh::fit {

struct TargetFitOptions {
  BaseOptions base;         ///< for a base built from the target (base.soup also reads the target's faces)
  FitOptions fit;
  AcceptanceRule acceptance;
};

struct TargetFit {
  /// The target's faces made a surface (they were given, and not ignored): it is fitted as one.
  bool target_is_surface = false;
  TriangleMeshData target_surface;  ///< when target_is_surface (notes moved to `notes`)
  Base base;
  /// The points fitted: a cloud's points, or a surface's vertices and points spread over its
  /// triangles (surface_samples).
  std::vector<Vec3> targets;
  FitResult result;
  TwoSidedDistances distances;
  Verdict verdict;
  std::vector<std::string> target_notes;  ///< what reading the target's faces did (repairs, splits)
  std::vector<std::string> notes;         ///< the base's, then the fit's
};

/// The first half: the target taken for what it is and the base. `base` when given, else one
/// made from the target (make_base). The target is `points` with their `faces` (none: a point
/// cloud; options.base.ignore_faces: treated as one) and `normals` (empty, or one per point). A
/// target whose faces are not a valid surface is an InputError saying how to make it one.
TargetFit prepare_target_fit(const PolygonSoup& target, const std::vector<Vec3>& normals,
                             const std::optional<Base>& base, const TargetFitOptions& options,
                             const StageControl& control = {});

/// The second half: the fit, its two-sided distances and the verdict (whether the surface
/// passes the two-sided check), filled into `prepared`. The verdict is set either way.
void run_target_fit(TargetFit& prepared, const TargetFitOptions& options,
                    const std::function<void(const IterationReport&)>& on_iteration = {},
                    const StageControl& control = {});

}  // namespace rgbmesh::fit
