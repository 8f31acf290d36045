// Poisson surface reconstruction (CGAL), bounded: see reconstruction_methods.hpp.
//
// CGAL's make_surface_mesh runs its mesher to the end, however long that is. On a Poisson
// function whose zero level set is far more complicated than the points (unoriented normals of
// a CAD export, a cloud with two layers, the function wrapping around sparse data) it ran for
// hours and took gigabytes. The mesher is therefore driven here one step at a time, as
// make_surface_mesh would drive it, with a vertex budget fixed before it starts: past it the
// level set is not a plausible base and the method gives up (MethodFailed), so that the
// automatic choice moves on to the advancing front.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>

#include <cmath>
#include <map>
#include <utility>

#include "reconstruction_methods.hpp"
#include "rgbmesh/fit/base.hpp"

namespace rgbmesh::fit::detail {
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
using Criteria = CGAL::Surface_mesh_default_criteria_3<MesherTriangulation>;
using MeshTraits = CGAL::Surface_mesh_traits_generator_3<ImplicitSurface>::type;
using Mesher = CGAL::Surface_mesher_generator<Complex, MeshTraits, Criteria, CGAL::Manifold_tag>::type;

// Called by the Poisson function before each batch of points enters its triangulation.
struct ControlVisitor {
  const StageControl* control;
  const std::string* stage;
  void before_insertion() const { control->step(*stage + " (Poisson equation)"); }
};

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

// The zero level set, meshed as a closed manifold whose facets have Delaunay balls of radius at
// most `radius` and lie within `distance` of the level set; MethodFailed past `max_vertices`.
PolygonSoup mesh_level_set(const PoissonFunction& function, double angle, double radius, double distance,
                           std::size_t max_vertices, const StageControl& control, const std::string& stage) {
  // The mesher searches inside a sphere around an inner point; five times the points' bounding
  // radius holds the whole level set. Its bisection tolerance follows the distance bound.
  const Point inner = function.get_inner_point();
  const double search_radius = 5 * std::sqrt(CGAL::to_double(function.bounding_sphere().squared_radius()));
  const ImplicitSurface surface(function, Kernel::Sphere_3(inner, search_radius * search_radius),
                                distance / 1000 / search_radius);
  const Criteria criteria(angle, radius, distance);
  MesherTriangulation triangulation;
  Complex complex(triangulation);
  const MeshTraits traits;
  // make_surface_mesh's start (20 points on the surface), then its loop, one step at a time.
  traits.construct_initial_points_object()(surface, CGAL::inserter(triangulation), 20);
  Mesher mesher(complex, surface, traits, criteria);
  mesher.init();
  CGAL::Null_mesh_visitor visitor;
  const std::string step_stage = stage + " (meshing the level set)";
  for (std::size_t steps = 0; !mesher.is_algorithm_done(); ++steps) {
    mesher.one_step(visitor);
    if (steps % 256 != 0) continue;
    const std::size_t vertices = triangulation.number_of_vertices();
    control.step(step_stage, std::min(0.99, static_cast<double>(vertices) / static_cast<double>(max_vertices)));
    if (vertices > max_vertices)
      throw MethodFailed("Poisson's zero level set needs more than " + with_thousands(max_vertices) +
                         " vertices: it is far more complicated than the points (are the normals oriented "
                         "consistently?)");
  }
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

// Whether every point lies in one plane (or on one line), by CGAL's exact predicates: a
// triangle of points spanning the plane, then every point's orientation to it.
bool in_one_plane(const std::vector<PointWithNormal>& samples) {
  if (samples.size() < 4) return true;
  const Point& a = samples[0].first;
  std::size_t b = 1;
  while (b < samples.size() && samples[b].first == a) ++b;
  std::size_t c = b + 1;
  while (c < samples.size() && CGAL::collinear(a, samples[b].first, samples[c].first)) ++c;
  if (c >= samples.size()) return true;  // all on one line
  for (const auto& [p, normal] : samples)
    if (CGAL::orientation(a, samples[b].first, samples[c].first, p) != CGAL::COPLANAR) return false;
  return true;
}

}  // namespace

PolygonSoup poisson_surface(const OrientedCloud& cloud, double spacing, double diagonal,
                            const ReconstructionOptions& options, const StageControl& control,
                            const std::string& stage) {
  std::vector<PointWithNormal> samples;
  samples.reserve(cloud.points.size());
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const Vec3 &p = cloud.points[i], &n = cloud.normals[i];
    samples.emplace_back(Point(p.x, p.y, p.z), Kernel::Vector_3(n.x, n.y, n.z));
  }
  // CGAL's solver needs a Delaunay triangulation of dimension 3: on points in one plane (CGAL's
  // own point_set_2.xyz, a 2D set with z = 0) it read past its arrays and crashed.
  if (in_one_plane(samples)) throw MethodFailed("the points lie in one plane: they enclose no volume");
  PoissonFunction function(samples.begin(), samples.end(), PointMap(), NormalMap());
  using Solver = CGAL::Eigen_solver_traits<
      Eigen::ConjugateGradient<CGAL::Eigen_sparse_symmetric_matrix<double>::EigenType>>;
  if (!function.compute_implicit_function(Solver(), ControlVisitor{&control, &stage}))
    throw MethodFailed("the Poisson equation could not be solved (are the normals consistently oriented?)");

  // Sizes fixed before meshing starts. The distance bound never asks for more accuracy than a
  // thousandth of the extent (the base is a decimation of this surface, and the fit moves it
  // onto the points anyway), and the vertex budget follows the faces wanted.
  const double distance = std::max(options.distance * spacing, 1e-3 * diagonal);
  const auto max_vertices = static_cast<std::size_t>(options.max_vertices_per_face * static_cast<double>(options.faces));
  // A first, coarse meshing gives the area; when it has too few facets, the radius bound is set
  // for about the number wanted (an equilateral facet of circumradius r has area 1.3 r², and the
  // mesher's facets are about half as large as its bound allows).
  PolygonSoup level_set = mesh_level_set(function, options.angle, options.radius * spacing, distance,
                                         max_vertices, control, stage);
  if (level_set.faces.empty()) throw MethodFailed("Poisson's implicit function has no zero level set");
  if (level_set.faces.size() < options.faces) {
    const double radius = std::sqrt(2 * area(level_set) / (1.3 * static_cast<double>(options.faces)));
    level_set = mesh_level_set(function, options.angle, radius, distance, max_vertices, control, stage);
  }
  return level_set;
}

}  // namespace rgbmesh::fit::detail
