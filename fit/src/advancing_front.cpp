// Advancing-front surface reconstruction (CGAL) and the filling of its small holes: see
// reconstruction_methods.hpp.
//
// The advancing front grows a surface from the most plausible Delaunay triangle through the
// points, adding neighbours while they keep the surface a manifold and plausible; it stops
// where the points stop, so an open scan stays open. Two additions:
//  * long triangles are refused (priority infinity): a triangle whose smallest Delaunay sphere
//    is more than `bridge` local spacings across joins points that the sampling does not join
//    (the two sides of a gap in a scene, a wall and the ground behind it);
//  * the holes it leaves where the sampling is locally thin (a few spacings around) are filled
//    afterwards, so that the base is not riddled with boundary loops that decimation must keep.

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <memory>

#include "reconstruction_methods.hpp"

namespace rgbmesh::fit::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A triangle may span this many local spacings (radius of its smallest Delaunay sphere).
constexpr double bridge = 3;

// CGAL's default priority (the radius of the smallest Delaunay sphere through the candidate),
// with long candidates refused, and the stage's control called now and then.
struct BoundedPriority {
  const std::vector<double>* spacing;
  const StageControl* control;
  const std::string* stage;
  std::shared_ptr<std::size_t> calls = std::make_shared<std::size_t>(0);

  template <typename AdvancingFront, typename CellHandle>
  double operator()(const AdvancingFront& front, CellHandle& cell, const int& index) const {
    if (++*calls % 4096 == 0) control->step(*stage + " (advancing front)");
    const double radius = front.smallest_radius_delaunay_sphere(cell, index);
    // The candidate's corners: the cell's vertices other than the one opposite the facet.
    double allowed = 0;
    for (int k = 1; k <= 3; ++k) {
      const auto v = cell->vertex((index + k) % 4);
      if (front.triangulation_3().is_infinite(v)) return std::numeric_limits<double>::infinity();
      allowed = std::max(allowed, (*spacing)[v->info()]);
    }
    return radius > bridge * allowed ? std::numeric_limits<double>::infinity() : radius;
  }
};

// Points in one plane: the Delaunay triangulation has dimension 2 (or less), which CGAL's
// advancing front does not handle (it read outside the triangulation and crashed, now and
// then, on CGAL's point_set_2.xyz, a 2D set with z = 0). The sheet is then the plane's Delaunay
// triangles, less those the priority above would refuse (spanning more than `bridge` local
// spacings), each corner's spacing as there.
template <class Delaunay>
PolygonSoup flat_sheet(const Delaunay& delaunay, const std::vector<Vec3>& points, const std::vector<double>& spacing) {
  PolygonSoup soup;
  soup.points = points;
  if (delaunay.dimension() == 2) {
    for (auto f = delaunay.finite_facets_begin(); f != delaunay.finite_facets_end(); ++f) {
      const auto cell = f->first;
      std::array<std::size_t, 3> corner{};
      double allowed = 0;
      for (int k = 0; k < 3; ++k) {
        corner[k] = cell->vertex(k)->info();
        allowed = std::max(allowed, spacing[corner[k]]);
      }
      const double radius = std::sqrt(CGAL::squared_radius(cell->vertex(0)->point(), cell->vertex(1)->point(),
                                                           cell->vertex(2)->point()));
      if (radius > bridge * allowed) continue;
      soup.faces.push_back({static_cast<std::int64_t>(corner[0]), static_cast<std::int64_t>(corner[1]),
                            static_cast<std::int64_t>(corner[2])});
    }
  }
  if (soup.faces.empty()) throw MethodFailed("the advancing front found no plausible triangle through the points");
  split_pinched_vertices(soup);  // (the advancing front's own surface has none)
  return soup;
}

}  // namespace

PolygonSoup advancing_front_surface(const std::vector<Vec3>& points, const std::vector<double>& spacing,
                                    const StageControl& control, const std::string& stage) {
  // The reconstruction's own triangulation, with each vertex knowing its point's index (the
  // priority reads the local spacing through it).
  using IndexedVertex = CGAL::Advancing_front_surface_reconstruction_vertex_base_3<
      Kernel, CGAL::Triangulation_vertex_base_with_info_3<std::size_t, Kernel>>;
  using CellBase = CGAL::Advancing_front_surface_reconstruction_cell_base_3<Kernel>;
  using Tds = CGAL::Triangulation_data_structure_3<IndexedVertex, CellBase>;
  using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
  using Reconstruction = CGAL::Advancing_front_surface_reconstruction<Delaunay, BoundedPriority>;

  std::vector<std::pair<Point, std::size_t>> indexed;
  indexed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) indexed.emplace_back(Point(points[i].x, points[i].y, points[i].z), i);
  control.step(stage + " (advancing front: Delaunay triangulation)");
  Delaunay delaunay(indexed.begin(), indexed.end());
  if (delaunay.dimension() < 3) return flat_sheet(delaunay, points, spacing);
  const BoundedPriority priority{&spacing, &control, &stage};
  Reconstruction reconstruction(delaunay, priority);
  reconstruction.run();  // CGAL's defaults: radius ratio bound 5, beta 0.52

  PolygonSoup soup;
  soup.points = points;
  const auto& surface = reconstruction.triangulation_data_structure_2();
  for (auto f = surface.faces_begin(); f != surface.faces_end(); ++f) {
    if (!f->is_on_surface()) continue;
    std::vector<std::int64_t> face;
    for (int k = 0; k < 3; ++k) face.push_back(static_cast<std::int64_t>(f->vertex(k)->vertex_3()->info()));
    soup.faces.push_back(std::move(face));
  }
  if (soup.faces.empty()) throw MethodFailed("the advancing front found no plausible triangle through the points");
  return soup;
}

std::size_t fill_small_holes(TriangleMeshData& mesh, double length) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vertex;
  vertex.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) vertex.push_back(sm.add_vertex(Point(p.x, p.y, p.z)));
  for (const auto& t : mesh.triangles)
    if (sm.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == SurfaceMesh::null_face())
      throw std::logic_error("fill_small_holes: a face of a checked mesh was refused by the halfedge structure");
  std::vector<SurfaceMesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  std::size_t filled = 0;
  for (const SurfaceMesh::Halfedge_index start : cycles) {
    double perimeter = 0;
    for (const auto h : CGAL::halfedges_around_face(start, sm))
      perimeter += std::sqrt(CGAL::squared_distance(sm.point(sm.source(h)), sm.point(sm.target(h))));
    if (perimeter > length) continue;
    std::vector<SurfaceMesh::Face_index> new_faces;
    std::vector<SurfaceMesh::Vertex_index> new_vertices;
    PMP::triangulate_and_refine_hole(sm, start, std::back_inserter(new_faces), std::back_inserter(new_vertices));
    filled += new_faces.empty() ? 0 : 1;
  }
  if (filled == 0) return 0;
  TriangleMeshData out;
  std::vector<std::int32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), -1);
  for (const auto v : sm.vertices()) {
    index[v] = static_cast<std::int32_t>(out.points.size());
    const Point& p = sm.point(v);
    out.points.emplace_back(p.x(), p.y(), p.z());
  }
  for (const auto f : sm.faces()) {
    std::array<std::int32_t, 3> t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k++] = index[v];
    out.triangles.push_back(t);
  }
  out.notes = std::move(mesh.notes);
  mesh = std::move(out);
  return filled;
}

}  // namespace rgbmesh::fit::detail
