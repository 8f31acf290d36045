#include "rgbmesh/fit/fit_target.hpp"

namespace rgbmesh::fit {

TargetFit prepare_target_fit(const PolygonSoup& target, const std::vector<Vec3>& normals,
                             const std::optional<Base>& base, const TargetFitOptions& options,
                             const StageControl& control) {
  TargetFit out;
  out.target_is_surface = !target.faces.empty() && !options.base.ignore_faces;
  if (out.target_is_surface) {
    out.target_surface = prepare_triangle_mesh(target, options.base.soup);
    out.target_notes = std::move(out.target_surface.notes);
    out.target_surface.notes.clear();
  }
  if (base) {
    out.base = *base;
  } else {
    // The checked surface, or the points alone.
    PolygonSoup from;
    if (out.target_is_surface) {
      from.points = out.target_surface.points;
      for (const auto& t : out.target_surface.triangles) from.faces.push_back({t[0], t[1], t[2]});
      from.sharp = out.target_surface.sharp;  // its creases, which the base keeps
    } else {
      from.points = target.points;
    }
    BaseOptions base_options = options.base;
    base_options.soup = SoupOptions();  // the surface is checked (and repaired) already
    out.base = make_base(from, out.target_is_surface ? std::vector<Vec3>{} : normals, base_options, control);
  }
  out.notes.insert(out.notes.end(), out.base.notes.begin(), out.base.notes.end());

  // A mesh target is a surface: the fit follows its triangles, not its vertices alone (a coarse
  // CAD mesh's limit surface would pass through the vertices and bulge between them).
  out.targets = out.target_is_surface
                    ? surface_samples(out.target_surface,
                                      target_sample_count(out.target_surface.points.size(),
                                                          out.base.mesh.triangles.size(), options.fit.levels))
                    : target.points;
  return out;
}

void run_target_fit(TargetFit& f, const TargetFitOptions& options,
                    const std::function<void(const IterationReport&)>& on_iteration, const StageControl& control) {
  // A cloud's targets are its points, so the surface they sample is measured from them.
  const TargetSurface surface =
      f.target_is_surface ? TargetSurface::from_mesh(f.target_surface) : TargetSurface::from_points(f.targets);
  // A mesh target is exact: what the noise measure would see in its samples is its edges and
  // corners, which more smoothing would only round off further.
  FitOptions fit_options = options.fit;
  if (f.target_is_surface) fit_options.noisy_above = 0;
  f.result = fit(f.base.mesh, f.targets, fit_options, on_iteration, control, &surface);
  f.notes.insert(f.notes.end(), f.result.notes.begin(), f.result.notes.end());
  f.distances = two_sided_distances(f.result, surface, control);
  // A mesh target is an exact surface: no allowance for noise in its points.
  AcceptanceRule rule = options.acceptance;
  if (f.target_is_surface) rule.rms_ratio = rule.max_ratio = 0;
  f.verdict = judge(f.distances, rule);
}

}  // namespace rgbmesh::fit
