// A base surface for a point cloud (see reconstruct.hpp): the cloud prepared once (sparsity,
// noise, size), then Poisson or the advancing front, each result checked against the points.
//
// Noise: CGAL's Poisson function is piecewise linear on a triangulation whose vertices are the
// input points, so its zero level set follows their noise. Where the noise is comparable to the
// spacing (CGAL's sphere_20k: noise 1.7 times the spacing) the surface gets bumps and tiny
// handles (genus 2 for a sphere), and decimation keeps every handle. Points are therefore first
// averaged over grid cells just large enough for the averaged noise to be small next to the new
// spacing; clean scans are left alone.

#include "rgbmesh/fit/reconstruct.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <utility>

#include "point_cloud.hpp"
#include "reconstruction_methods.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/geometry.hpp"

namespace rgbmesh::fit {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using PointWithNormal = std::pair<Point, Kernel::Vector_3>;
using PointMap = CGAL::First_of_pair_property_map<PointWithNormal>;
using NormalMap = CGAL::Second_of_pair_property_map<PointWithNormal>;

// The fewest points for which normals and a surface make sense at all.
constexpr std::size_t fewest_points = 10;

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, fraction < 0.1 ? "%.2g%%" : "%.0f%%", 100 * fraction);
  return text;
}

bool usable(const Vec3& n) { return is_finite(n) && norm(n) > 0; }

// CGAL's jet fitting and minimum-spanning-tree orientation over (point, normal) pairs. Jet
// fitting replaces the directions (estimate = true); the spanning tree then orients them from
// the highest point, whose normal points up. Points the tree cannot reach keep no reliable
// orientation and are dropped; returns how many.
std::size_t orient_normals(std::vector<PointWithNormal>& samples, int neighbours, bool estimate) {
  const auto k = static_cast<unsigned>(neighbours);
  const auto maps = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());
  if (estimate) CGAL::jet_estimate_normals<CGAL::Sequential_tag>(samples, k, maps);
  const auto unoriented = CGAL::mst_orient_normals(samples, k, maps);
  const auto dropped = static_cast<std::size_t>(std::distance(unoriented, samples.end()));
  samples.erase(unoriented, samples.end());
  return dropped;
}

// The fraction of neighbouring pairs (8 nearest) whose normals point away from each other: near 0
// for oriented normals (the two sides of thin parts add a little), near one half for normals
// whose signs are arbitrary (principal directions of a CAD export, say).
double disagreeing_neighbours(const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
  const detail::PointIndex index(points);
  std::vector<std::pair<std::size_t, double>> near;
  std::size_t pairs = 0, opposite = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    index.nearest(points[i], 9, near);
    for (const auto& [j, d] : near) {
      if (j == i) continue;
      ++pairs;
      opposite += dot(normals[i], normals[j]) < 0;
    }
  }
  return pairs == 0 ? 0.0 : static_cast<double>(opposite) / static_cast<double>(pairs);
}

// Oriented unit normals for Poisson: the file's where usable and consistent, else estimated.
detail::OrientedCloud oriented_cloud(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                     int neighbours, std::vector<std::string>& notes) {
  std::vector<PointWithNormal> samples;
  samples.reserve(points.size());
  std::size_t unusable = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (!normals.empty() && !usable(normals[i])) {
      ++unusable;
      continue;
    }
    const Vec3 n = normals.empty() ? Vec3() : normals[i] * (1.0 / norm(normals[i]));
    samples.emplace_back(Point(p.x, p.y, p.z), Kernel::Vector_3(n.x, n.y, n.z));
  }
  bool estimate = normals.empty(), reorient = estimate;
  if (unusable > 0 && 2 * unusable > points.size()) {
    notes.push_back(with_thousands(unusable) + " of " + with_thousands(points.size()) +
                    " normals are zero or not finite: the normals are estimated from the points instead");
    samples.clear();
    for (const Vec3& p : points) samples.emplace_back(Point(p.x, p.y, p.z), Kernel::Vector_3(0, 0, 0));
    estimate = reorient = true;
  } else if (unusable > 0) {
    notes.push_back(
        with_thousands(unusable) + " of " + with_thousands(points.size()) +
        " normals are zero or not finite: those points are left out of the reconstruction (they are "
        "still fitted)");
  }
  if (!estimate) {
    std::vector<Vec3> p, n;
    for (const auto& [q, m] : samples) {
      p.emplace_back(q.x(), q.y(), q.z());
      n.emplace_back(m.x(), m.y(), m.z());
    }
    // A tenth of disagreeing pairs is far more than the thin parts of real scans give (CGAL's
    // oriented clouds: under 2%), and far less than arbitrary signs (about a half).
    if (const double opposite = disagreeing_neighbours(p, n); opposite > 0.1) {
      notes.push_back(
          "the file's normals are not consistently oriented (" + percent(opposite) +
          " of neighbouring normals point opposite ways): they are re-oriented along a spanning tree");
      reorient = true;
    }
  }
  if (reorient) {
    const std::size_t dropped = orient_normals(samples, neighbours, estimate);
    if (dropped > 0)
      notes.push_back("normal orientation could not reach " + with_thousands(dropped) + " of " +
                      with_thousands(points.size()) + " points: they are left out of the reconstruction");
  }
  detail::OrientedCloud cloud;
  for (const auto& [q, m] : samples) {
    cloud.points.emplace_back(q.x(), q.y(), q.z());
    cloud.normals.emplace_back(m.x(), m.y(), m.z());
  }
  return cloud;
}

// Noisy clouds averaged over grid cells (see the file's comment), and large ones down to about
// `max_points`: the same cell means, on coarser cells.
detail::OrientedCloud working_cloud(const detail::OrientedCloud& cloud, const detail::CloudScale& scale,
                                    const ReconstructionOptions& options, std::vector<std::string>& notes) {
  double cell = detail::denoising_cell(scale, options.noise_to_spacing);
  const bool noisy = cell > 0;
  if (cloud.points.size() > options.max_points)
    cell = std::max(cell, scale.spacing * std::sqrt(static_cast<double>(cloud.points.size()) /
                                                    static_cast<double>(options.max_points)));
  if (!(cell > 0)) return cloud;
  detail::OrientedCloud out;
  for (;; cell *= 1.25) {
    out.points = detail::cell_means(cloud.points, cloud.normals, cell, out.normals);
    if (out.points.size() <= options.max_points) break;
  }
  char text[240];
  if (noisy)
    std::snprintf(
        text, sizeof text,
        "the points are noisy (%.2g, %.2g times their spacing): the surface is reconstructed from %s "
        "averages over cells of %.2g",
        scale.noise, scale.noise / scale.spacing, with_thousands(out.points.size()).c_str(), cell);
  else
    std::snprintf(
        text, sizeof text,
        "the surface is reconstructed from %s averages of the points over cells of %.2g (at most %s "
        "points; the fit uses every point)",
        with_thousands(out.points.size()).c_str(), cell, with_thousands(options.max_points).c_str());
  notes.push_back(text);
  return out;
}

// The connected components (by triangles) of a checked mesh that hold at least `share` of its
// triangles (the largest always), with the number of others dropped.
std::pair<TriangleMeshData, std::size_t> main_components(const TriangleMeshData& mesh, double share) {
  std::vector<std::int32_t> parent(mesh.points.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : mesh.triangles) {
    parent[find(t[1])] = find(t[0]);
    parent[find(t[2])] = find(t[0]);
  }
  std::map<std::int32_t, std::size_t> triangles_of;
  for (const auto& t : mesh.triangles) ++triangles_of[find(t[0])];
  std::size_t largest = 0;
  for (const auto& [root, n] : triangles_of) largest = std::max(largest, n);
  const auto kept = [&](std::int32_t root) {
    const std::size_t n = triangles_of[root];
    return n == largest || static_cast<double>(n) >= share * static_cast<double>(mesh.triangles.size());
  };
  std::size_t dropped = 0;
  for (const auto& [root, n] : triangles_of) dropped += kept(root) ? 0 : 1;
  PolygonSoup soup;
  soup.points = mesh.points;
  for (const auto& t : mesh.triangles)
    if (kept(find(t[0]))) soup.faces.push_back({t[0], t[1], t[2]});
  // prepare_triangle_mesh drops the other components' vertices (that note is not news).
  TriangleMeshData out = prepare_triangle_mesh(soup);
  out.notes.clear();
  return {std::move(out), dropped};
}

// Six times the signed volume enclosed (positive when the triangles face outwards).
double signed_volume6(const TriangleMeshData& mesh) {
  double volume = 0;
  for (const auto& t : mesh.triangles)
    volume += dot(mesh.points[t[0]], cross(mesh.points[t[1]], mesh.points[t[2]]));
  return volume;
}

// The fraction of the surface's area whose triangles' centroids lie farther than `spacings` local
// spacings from the surface the points sample (the nearest point's disc, as the fit's check
// measures it: TargetSurface). On CGAL's closed scans Poisson's surface measures 0 at two
// spacings (clean or averaged: kitten, ball, sphere_20k, blobby); where it closes an opening
// of the scan, its cap does not (one side of a hippo, hippo1: 65%).
double unsupported_fraction(const TriangleMeshData& mesh, const std::vector<Vec3>& points,
                            const detail::PointIndex& index, const std::vector<double>& spacing,
                            double spacings) {
  std::vector<Vec3> centroids;
  std::vector<double> areas;
  centroids.reserve(mesh.triangles.size());
  areas.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    centroids.push_back((a + b + c) * (1.0 / 3));
    areas.push_back(0.5 * norm(cross(b - a, c - a)));
  }
  const std::vector<double> d = TargetSurface::from_points(points).distances(centroids);
  double total = 0, unsupported = 0;
  for (std::size_t i = 0; i < centroids.size(); ++i) {
    total += areas[i];
    if (d[i] > spacings * spacing[index.nearest(centroids[i]).first]) unsupported += areas[i];
  }
  return total > 0 ? unsupported / total : 0.0;
}

// A method's soup as a checked base: its components of at least 5% of the triangles (the pieces
// of a scene, or the parts of an object that the sampling leaves apart; smaller ones are debris
// of noise, and a note counts them). MethodFailed when it is not a valid mesh.
TriangleMeshData checked_surface(const PolygonSoup& soup, const char* method,
                                 std::vector<std::string>& notes) {
  try {
    auto [mesh, dropped] = main_components(prepare_triangle_mesh(soup), 0.05);
    if (dropped > 0)
      notes.push_back(std::string("the ") + method + " surface has " + with_thousands(dropped) +
                      " small components (each under 5% of its triangles): dropped");
    return std::move(mesh);
  } catch (const InputError& e) {
    throw detail::MethodFailed(std::string("the ") + method + " surface is not a valid mesh: " + e.what());
  }
}

struct Cloud {
  std::vector<Vec3> points;
  detail::PointIndex index;
  std::vector<double> spacing;
  std::vector<double> support;  // detail::support_spacing
  explicit Cloud(std::vector<Vec3> p)
      : points(std::move(p)),
        index(points),
        spacing(detail::local_spacing(points, index)),
        support(detail::support_spacing(spacing)) {}
};

Reconstruction by_poisson(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                          const detail::CloudScale& scale, double diagonal,
                          const ReconstructionOptions& options, const StageControl& control,
                          const std::string& stage) {
  Reconstruction r;
  r.method = ReconstructionMethod::poisson;
  std::vector<std::string>& notes = r.mesh.notes;
  const detail::OrientedCloud oriented = oriented_cloud(points, normals, options.neighbours, notes);
  if (oriented.points.size() < fewest_points)
    throw detail::MethodFailed("too few points with oriented normals");
  const detail::OrientedCloud working = working_cloud(oriented, scale, options, notes);
  const PolygonSoup level_set =
      detail::poisson_surface(working, scale.spacing, diagonal, options, control, stage);
  TriangleMeshData mesh = checked_surface(level_set, "Poisson", notes);
  if (signed_volume6(mesh) < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const Cloud cloud(working.points);
  r.unsupported =
      unsupported_fraction(mesh, cloud.points, cloud.index, cloud.support, options.support_spacings);
  if (options.method == ReconstructionMethod::automatic && r.unsupported > options.max_unsupported)
    throw detail::MethodFailed(
        percent(r.unsupported) +
        " of Poisson's closed surface lies farther than twice the points' spacing from "
        "the surface they sample: they do not enclose a volume (an open scan, or a scene)");
  r.mesh.points = std::move(mesh.points);
  r.mesh.triangles = std::move(mesh.triangles);
  return r;
}

Reconstruction by_advancing_front(const std::vector<Vec3>& points, const detail::CloudScale& scale,
                                  const ReconstructionOptions& options, const StageControl& control,
                                  const std::string& stage) {
  Reconstruction r;
  r.method = ReconstructionMethod::advancing_front;
  std::vector<std::string>& notes = r.mesh.notes;
  detail::OrientedCloud plain;
  plain.points = points;
  const detail::OrientedCloud working = working_cloud(plain, scale, options, notes);
  const Cloud cloud(working.points);
  const PolygonSoup soup = detail::advancing_front_surface(cloud.points, cloud.spacing, control, stage);
  TriangleMeshData mesh = checked_surface(soup, "advancing-front", notes);
  // The kept piece must hold most of the points: otherwise they are several surfaces, or none.
  const double held = static_cast<double>(mesh.points.size()) / static_cast<double>(cloud.points.size());
  if (held < 0.5)
    throw detail::MethodFailed("the largest surface through the points holds only " + percent(held) +
                               " of them: they do not sample one surface densely enough");
  std::vector<double> sorted = cloud.spacing;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const double median_spacing = sorted[sorted.size() / 2];
  if (const std::size_t filled =
          detail::fill_small_holes(mesh, options.fill_holes_shorter_than * median_spacing);
      filled > 0)
    notes.push_back("filled " + with_thousands(filled) +
                    " small holes of the advancing-front surface (gaps of the "
                    "sampling, shorter than " +
                    with_thousands(static_cast<std::size_t>(options.fill_holes_shorter_than)) +
                    " spacings around)");
  try {
    topology_of(mesh);
  } catch (const InputError& e) {
    throw detail::MethodFailed(std::string("the advancing-front surface is not a valid base: ") + e.what());
  }
  r.unsupported =
      unsupported_fraction(mesh, cloud.points, cloud.index, cloud.support, options.support_spacings);
  r.mesh.points = std::move(mesh.points);
  r.mesh.triangles = std::move(mesh.triangles);
  return r;
}

}  // namespace

const char* to_string(ReconstructionMethod method) {
  switch (method) {
    case ReconstructionMethod::automatic:
      return "automatic";
    case ReconstructionMethod::poisson:
      return "poisson";
    default:
      return "advancing-front";
  }
}

bool reconstruction_method_from_name(const std::string& name, ReconstructionMethod& method) {
  for (const ReconstructionMethod m : {ReconstructionMethod::automatic, ReconstructionMethod::poisson,
                                       ReconstructionMethod::advancing_front}) {
    if (name == to_string(m)) {
      method = m;
      return true;
    }
  }
  return false;
}

Reconstruction reconstruct_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                   const ReconstructionOptions& options, const StageControl& control) {
  const auto start = std::chrono::steady_clock::now();
  const std::string stage = "reconstructing a surface from " + with_thousands(points.size()) + " points";
  const auto refuse = [&](const std::string& why) { return InputError(stage + ": " + why); };
  if (points.size() < fewest_points)
    throw refuse("too few points (at least " + std::to_string(fewest_points) + " are needed)");
  if (!normals.empty() && normals.size() != points.size())
    throw std::invalid_argument("reconstruct_surface: " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(points.size()) + " points");
  // CGAL's default random generator (seeded from the clock, advanced by every earlier use in the
  // process) drives the mesher's starting points and the triangulations' point location: a fixed
  // seed makes the same cloud give the same surface in every run and whatever ran before.
  CGAL::get_default_random() = CGAL::Random(0);
  control.step(stage);
  const detail::CloudScale scale = detail::measure_scale(points, options.neighbours);
  if (!(scale.spacing > 0)) throw refuse("the points have no spread (they coincide)");
  const double diagonal = bounding_box_diagonal(points);
  if (scale.spacing > options.max_spacing_to_diagonal * diagonal)
    throw refuse("the points are too sparse to determine a surface: their spacing is " +
                 percent(scale.spacing / diagonal) + " of their extent (at most " +
                 percent(options.max_spacing_to_diagonal) +
                 ", about 500 points spread over an object); give more points, or a base mesh (--base) whose "
                 "control points the fit moves onto them");

  Reconstruction result;
  std::string poisson_failure;
  if (options.method != ReconstructionMethod::advancing_front) {
    try {
      result = by_poisson(points, normals, scale, diagonal, options, control, stage);
    } catch (const detail::MethodFailed& e) {
      poisson_failure = e.what();
      if (options.method == ReconstructionMethod::poisson)
        throw refuse(poisson_failure +
                     " (--reconstruction advancing-front reconstructs through the points instead)");
    }
  }
  if (options.method == ReconstructionMethod::advancing_front || !poisson_failure.empty()) {
    try {
      result = by_advancing_front(points, scale, options, control, stage);
    } catch (const detail::MethodFailed& e) {
      throw refuse((poisson_failure.empty() ? "" : "Poisson: " + poisson_failure + "; advancing front: ") +
                   e.what() + ". Give a base mesh (--base FILE) for the fit to move, or more points");
    }
    if (!poisson_failure.empty())
      result.mesh.notes.insert(
          result.mesh.notes.begin(),
          "Poisson: " + poisson_failure +
              ": the surface is reconstructed through the points instead (advancing front; "
              "open where they are)");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

void detail::split_pinched_vertices(PolygonSoup& soup) {
  // (one pass: a split adds no pinch elsewhere; triangles across an edge share both fans)
  std::vector<std::vector<std::size_t>> around(soup.points.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    for (const std::int64_t v : soup.faces[f]) around[static_cast<std::size_t>(v)].push_back(f);
  for (std::size_t v = 0; v < around.size(); ++v) {
    const std::vector<std::size_t>& fan = around[v];
    if (fan.size() < 2) continue;
    // Fans: the triangles at v joined through their other corners (an edge (v, w) is shared).
    std::vector<std::size_t> group(fan.size());
    std::iota(group.begin(), group.end(), 0);
    const auto find = [&](std::size_t x) {
      while (group[x] != x) x = group[x] = group[group[x]];
      return x;
    };
    std::map<std::int64_t, std::size_t> first_at;  // other corner -> the first triangle with it
    for (std::size_t i = 0; i < fan.size(); ++i)
      for (const std::int64_t w : soup.faces[fan[i]]) {
        if (w == static_cast<std::int64_t>(v)) continue;
        const auto [it, fresh] = first_at.try_emplace(w, i);
        if (!fresh) group[find(i)] = find(it->second);
      }
    std::map<std::size_t, std::size_t> sizes;
    for (std::size_t i = 0; i < fan.size(); ++i) ++sizes[find(i)];
    if (sizes.size() < 2) continue;
    const std::size_t largest =
        std::max_element(sizes.begin(), sizes.end(), [](const auto& x, const auto& y) {
          return x.second < y.second;
        })->first;
    std::map<std::size_t, std::int64_t> copy_of;  // fan -> its vertex
    for (std::size_t i = 0; i < fan.size(); ++i) {
      const std::size_t which = find(i);
      if (which == largest) continue;
      auto [it, fresh] = copy_of.try_emplace(which, static_cast<std::int64_t>(soup.points.size()));
      if (fresh) soup.points.push_back(soup.points[v]);
      for (std::int64_t& corner : soup.faces[fan[i]])
        if (corner == static_cast<std::int64_t>(v)) corner = it->second;
    }
  }
}

double detail::trim_unsupported(TriangleMeshData& mesh, const std::vector<Vec3>& points, double spacings,
                                bool border_only) {
  if (points.size() < 2 || mesh.triangles.empty()) return 0;
  const PointIndex index(points);
  const std::vector<double> spacing = support_spacing(local_spacing(points, index));
  const auto supported = [&](const Vec3& p) {
    const auto [nearest, distance] = index.nearest(p);
    return distance <= spacings * spacing[nearest];
  };
  PolygonSoup soup;
  soup.points = mesh.points;
  // With border_only, only the triangles along the boundary are tested (those with an edge of
  // one triangle): a coarse mesh's border is peeled back to the points without cutting into its
  // covered interior, where large triangles leave the points by their curvature alone.
  std::vector<char> on_border(mesh.triangles.size(), !border_only);
  if (border_only) {
    std::map<std::pair<std::int32_t, std::int32_t>, int> uses;
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const auto& t = mesh.triangles[i];
        if (uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}] == 1) on_border[i] = 1;
      }
  }
  double area = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    const double triangle_area = 0.5 * norm(cross(b - a, c - a));
    area += triangle_area;
    if (!on_border[i] || (supported((a + b + c) * (1.0 / 3)) && supported((a + b) * 0.5) &&
                          supported((b + c) * 0.5) && supported((c + a) * 0.5)))
      soup.faces.push_back({t[0], t[1], t[2]});
  }
  if (soup.faces.size() == mesh.triangles.size() || soup.faces.empty()) return 0;
  // Where trimmed parts met only at a vertex (a part of the scan held to the rest by a vertex
  // only is still scanned: CGAL's hippo2 has such a lobe of 56 points).
  split_pinched_vertices(soup);
  try {
    // Pieces that the trimming cut off and that hold under 0.5% of the triangles are debris
    // (islands of a few triangles over gaps); larger ones are parts of the scan.
    TriangleMeshData trimmed = main_components(prepare_triangle_mesh(soup), 0.005).first;
    topology_of(trimmed);
    double kept = 0;
    for (const auto& t : trimmed.triangles)
      kept += 0.5 * norm(cross(trimmed.points[t[1]] - trimmed.points[t[0]],
                               trimmed.points[t[2]] - trimmed.points[t[0]]));
    trimmed.notes = std::move(mesh.notes);
    mesh = std::move(trimmed);
    return area > 0 ? 1 - kept / area : 0;
  } catch (const InputError&) {
    return 0;  // not a valid surface once trimmed: kept whole
  }
}

}  // namespace rgbmesh::fit
