// A base surface for a point cloud: CGAL's Poisson surface reconstruction (see base.hpp).
//
// Poisson reconstruction was chosen because it yields a closed, watertight surface through a
// scan without parameters to tune beyond the point spacing, which the points give: that is the
// kind of base a closed scanned object needs. Two things are added around it:
//  * noise: CGAL's Poisson function is piecewise linear on a triangulation whose vertices are the
//    input points, so its zero level set follows their noise. Where the noise is comparable to
//    the spacing (CGAL's sphere_20k: noise 1.7 times the spacing) the surface gets bumps and
//    tiny handles (genus 2 for a sphere), and decimation keeps every handle. Points are
//    therefore first averaged over grid cells just large enough for the averaged noise to be
//    small next to the new spacing; clean scans are left alone;
//  * size: the zero level set is meshed finely enough (a few times the base's faces) for the
//    decimation to choose where the base's vertices go.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "point_cloud.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/geometry.hpp"

namespace rgbmesh::fit {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using PointWithNormal = std::pair<Point, Kernel::Vector_3>;
using PointMap = CGAL::First_of_pair_property_map<PointWithNormal>;
using NormalMap = CGAL::Second_of_pair_property_map<PointWithNormal>;
using PoissonFunction = CGAL::Poisson_reconstruction_function<Kernel>;
using MesherTriangulation = CGAL::Surface_mesh_default_triangulation_3;
using Complex = CGAL::Surface_mesh_complex_2_in_triangulation_3<MesherTriangulation>;
using ImplicitSurface = CGAL::Implicit_surface_3<Kernel, PoissonFunction>;

// The fewest points for which normals and a Poisson surface make sense at all.
constexpr std::size_t fewest_points = 10;

Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
Vec3 vec(const Kernel::Vector_3& v) { return {v.x(), v.y(), v.z()}; }

// Normals for unoriented points: jet fitting gives the direction, a minimum spanning tree over
// the k-nearest-neighbour graph the orientation (from the highest point, whose normal points
// up). Points the tree cannot reach keep no reliable orientation and are dropped.
std::size_t estimate_normals(std::vector<PointWithNormal>& points, int neighbours) {
  const auto k = static_cast<unsigned>(neighbours);
  const auto maps = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());
  CGAL::jet_estimate_normals<CGAL::Sequential_tag>(points, k, maps);
  const auto unoriented = CGAL::mst_orient_normals(points, k, maps);
  const auto dropped = static_cast<std::size_t>(std::distance(unoriented, points.end()));
  points.erase(unoriented, points.end());
  return dropped;
}

// The facets of the meshed complex as a soup (orientation is made consistent afterwards by
// prepare_triangle_mesh).
PolygonSoup facets_of(const Complex& complex) {
  PolygonSoup soup;
  std::map<MesherTriangulation::Vertex_handle, std::int64_t> index;
  for (auto f = complex.facets_begin(); f != complex.facets_end(); ++f) {
    std::vector<std::int64_t> face;
    for (int k = 1; k <= 3; ++k) {
      const MesherTriangulation::Vertex_handle v = f->first->vertex((f->second + k) % 4);
      const auto [it, inserted] = index.emplace(v, static_cast<std::int64_t>(soup.points.size()));
      if (inserted) soup.points.emplace_back(v->point().x(), v->point().y(), v->point().z());
      face.push_back(it->second);
    }
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

// The zero level set of the function, meshed as a closed manifold whose facets have Delaunay
// balls of radius at most `radius` and lie within `distance` of the level set.
PolygonSoup mesh_level_set(const PoissonFunction& function, double angle, double radius, double distance) {
  // The mesher searches inside a sphere around an inner point; five times the points' bounding
  // radius holds the whole level set. Its bisection tolerance follows the distance bound.
  const Point inner = function.get_inner_point();
  const double search_radius = 5 * std::sqrt(CGAL::to_double(function.bounding_sphere().squared_radius()));
  const ImplicitSurface surface(function, Kernel::Sphere_3(inner, search_radius * search_radius),
                                distance / 1000 / search_radius);
  const CGAL::Surface_mesh_default_criteria_3<MesherTriangulation> criteria(angle, radius, distance);
  MesherTriangulation triangulation;
  Complex complex(triangulation);
  CGAL::make_surface_mesh(complex, surface, criteria, CGAL::Manifold_tag());
  return facets_of(complex);
}

double area(const PolygonSoup& soup) {
  double sum = 0;
  for (const auto& f : soup.faces) {
    const Vec3 &a = soup.points[f[0]], &b = soup.points[f[1]], &c = soup.points[f[2]];
    sum += 0.5 * norm(cross(b - a, c - a));
  }
  return sum;
}

// The largest connected component (by triangles) of a checked mesh, with the number of others.
std::pair<TriangleMeshData, std::size_t> largest_component(const TriangleMeshData& mesh) {
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
  const auto largest =
      std::max_element(triangles_of.begin(), triangles_of.end(), [](const auto& a, const auto& b) {
        return a.second < b.second;
      })->first;
  PolygonSoup kept;
  kept.points = mesh.points;
  for (const auto& t : mesh.triangles)
    if (find(t[0]) == largest) kept.faces.push_back({t[0], t[1], t[2]});
  // prepare_triangle_mesh drops the other components' vertices (that note is not news).
  TriangleMeshData out = prepare_triangle_mesh(kept);
  out.notes.clear();
  return {std::move(out), triangles_of.size() - 1};
}

// Six times the signed volume enclosed (positive when the triangles face outwards).
double signed_volume6(const TriangleMeshData& mesh) {
  double volume = 0;
  for (const auto& t : mesh.triangles)
    volume += dot(mesh.points[t[0]], cross(mesh.points[t[1]], mesh.points[t[2]]));
  return volume;
}

}  // namespace

TriangleMeshData reconstruct_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                     const ReconstructionOptions& options) {
  const std::string stage = "reconstructing a surface from " + with_thousands(points.size()) + " points: ";
  if (points.size() < fewest_points)
    throw InputError(stage + "too few points (at least " + std::to_string(fewest_points) + " are needed)");
  if (!normals.empty() && normals.size() != points.size())
    throw std::invalid_argument("reconstruct_surface: " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(points.size()) + " points");
  // CGAL's default random generator (seeded from the clock, advanced by every earlier use in the
  // process) drives the mesher's starting points and the triangulations' point location: a fixed
  // seed makes the same cloud give the same surface in every run and whatever ran before.
  CGAL::get_default_random() = CGAL::Random(0);
  TriangleMeshData result;
  std::vector<PointWithNormal> samples;
  samples.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const Vec3 n = normals.empty() ? Vec3() : normals[i] * (1.0 / norm(normals[i]));
    samples.emplace_back(Point(p.x, p.y, p.z), Kernel::Vector_3(n.x, n.y, n.z));
  }
  if (normals.empty()) {
    const std::size_t dropped = estimate_normals(samples, options.neighbours);
    if (dropped > 0)
      result.notes.push_back("normal estimation could not orient " + with_thousands(dropped) + " of " +
                             with_thousands(points.size()) +
                             " points: the surface is reconstructed without them");
    if (samples.size() < fewest_points) throw InputError(stage + "too few points with oriented normals");
  }

  std::vector<Vec3> positions, directions;
  for (const auto& [p, n] : samples) {
    positions.push_back(vec(p));
    directions.push_back(vec(n));
  }
  const detail::CloudScale scale = detail::measure_scale(positions, options.neighbours);
  if (!(scale.spacing > 0)) throw InputError(stage + "the points have no spread (they coincide)");
  if (const double cell = detail::denoising_cell(scale, options.noise_to_spacing); cell > 0) {
    std::vector<Vec3> mean_normals;
    const std::vector<Vec3> means = detail::cell_means(positions, directions, cell, mean_normals);
    samples.clear();
    for (std::size_t i = 0; i < means.size(); ++i)
      samples.emplace_back(Point(means[i].x, means[i].y, means[i].z),
                           Kernel::Vector_3(mean_normals[i].x, mean_normals[i].y, mean_normals[i].z));
    char text[200];
    std::snprintf(
        text, sizeof text,
        "the points are noisy (%.2g, %.2g times their spacing): the surface is reconstructed from %s "
        "averages over cells of %.2g",
        scale.noise, scale.noise / scale.spacing, with_thousands(samples.size()).c_str(), cell);
    result.notes.push_back(text);
    if (samples.size() < fewest_points) throw InputError(stage + "too few points after averaging the noise");
  }

  PoissonFunction function(samples.begin(), samples.end(), PointMap(), NormalMap());
  if (!function.compute_implicit_function())
    throw InputError(stage +
                     "the Poisson equation could not be solved (are the normals consistently oriented?)");
  const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
      samples, 6, CGAL::parameters::point_map(PointMap()));
  // A first, coarse meshing gives the area; when it has too few facets, the radius bound is set
  // for about the number wanted (an equilateral facet of circumradius r has area 1.3 r², and the
  // mesher's facets are about half as large as its bound allows).
  PolygonSoup level_set =
      mesh_level_set(function, options.angle, options.radius * spacing, options.distance * spacing);
  if (level_set.faces.empty()) throw InputError(stage + "the implicit surface has no zero level set");
  if (level_set.faces.size() < options.faces) {
    const double radius = std::sqrt(2 * area(level_set) / (1.3 * static_cast<double>(options.faces)));
    level_set = mesh_level_set(function, options.angle, radius, options.distance * spacing);
  }

  try {
    auto [mesh, others] = largest_component(prepare_triangle_mesh(level_set));
    if (others > 0)
      result.notes.push_back("the reconstruction has " + with_thousands(others + 1) +
                             " components: the largest is kept, " + with_thousands(others) + " dropped");
    if (signed_volume6(mesh) < 0)
      for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    topology_of(mesh);  // the checks of a base
    result.points = std::move(mesh.points);
    result.triangles = std::move(mesh.triangles);
  } catch (const InputError& e) {
    throw InputError(stage + "the reconstructed surface is not a valid mesh: " + e.what());
  }
  return result;
}

}  // namespace rgbmesh::fit
