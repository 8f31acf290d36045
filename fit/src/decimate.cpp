// Topology-preserving decimation with CGAL's edge collapse (see base.hpp for the contract).
//
// VTK's quadric decimation, used before, collapses edges without the link condition and
// returned non-manifold meshes (edges shared by four triangles on the cow, pinched vertices on
// the elephant with holes). CGAL's edge_collapse refuses every collapse that would break the
// link condition, close a triangular hole or pinch a boundary, so the topology survives; the
// bounded-normal-change filter also refuses collapses that would flip a triangle. The result is
// nevertheless checked with rgbmesh's own checks, the ones every base must pass.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <algorithm>
#include <map>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <string>
#include <vector>

#include "rgbmesh/fit/base.hpp"

namespace rgbmesh::fit {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace SMS = CGAL::Surface_mesh_simplification;

SurfaceMesh to_surface_mesh(const TriangleMeshData& mesh) {
  SurfaceMesh out;
  out.reserve(static_cast<SurfaceMesh::size_type>(mesh.points.size()),
              static_cast<SurfaceMesh::size_type>(3 * mesh.triangles.size() / 2 + 1),
              static_cast<SurfaceMesh::size_type>(mesh.triangles.size()));
  std::vector<SurfaceMesh::Vertex_index> vertex;
  vertex.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) vertex.push_back(out.add_vertex(Kernel::Point_3(p.x, p.y, p.z)));
  for (const auto& t : mesh.triangles) {
    // The input passed prepare_triangle_mesh (manifold, consistently oriented), so CGAL's
    // halfedge structure accepts every face.
    if (out.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == SurfaceMesh::null_face())
      throw std::logic_error("decimate: a face of a checked mesh was refused by the halfedge structure");
  }
  return out;
}

// The collapsed mesh with its vertices renumbered densely (collapses leave holes in CGAL's
// numbering), as the checks and RgbMesh expect.
PolygonSoup to_soup(const SurfaceMesh& mesh, std::vector<std::int64_t>* numbering = nullptr) {
  PolygonSoup soup;
  std::vector<std::int64_t> own;
  std::vector<std::int64_t>& index = numbering ? *numbering : own;
  index.assign(mesh.num_vertices(), -1);
  for (const SurfaceMesh::Vertex_index v : mesh.vertices()) {
    index[v] = static_cast<std::int64_t>(soup.points.size());
    const Kernel::Point_3& p = mesh.point(v);
    soup.points.emplace_back(p.x(), p.y(), p.z());
  }
  for (const SurfaceMesh::Face_index f : mesh.faces()) {
    std::vector<std::int64_t> face;
    for (const SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      face.push_back(index[v]);
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

// CGAL's stop predicates count edges; the user asks for faces, and on a surface with boundary
// the two are not proportional.
class FaceCountReached {
 public:
  FaceCountReached(const SurfaceMesh& mesh, std::size_t faces) : mesh_(mesh), faces_(faces) {}
  template <class Cost, class Profile>
  bool operator()(const Cost&, const Profile&, std::size_t, std::size_t) const {
    return mesh_.number_of_faces() <= faces_;
  }

 private:
  const SurfaceMesh& mesh_;
  std::size_t faces_;
};

// Calls the stage's control every 1,024 edges taken from the queue (the fraction is that of the
// collapses needed, roughly: the initial edge count down to the goal's).
class ControlVisitor : public SMS::Edge_collapse_visitor_base<SurfaceMesh> {
 public:
  ControlVisitor(const StageControl& control, const std::string& stage, std::size_t from, std::size_t to)
      : control_(&control), stage_(&stage), from_(from), to_(to) {}
  void OnSelected(const Profile&, const boost::optional<double>&, std::size_t initial, std::size_t current) {
    if (++*selected_ % 1024 != 0) return;
    const double needed = static_cast<double>(initial) * (1.0 - static_cast<double>(to_) / static_cast<double>(from_));
    control_->step(*stage_, needed > 0 ? std::min(1.0, static_cast<double>(initial - current) / needed) : -1);
  }

 private:
  const StageControl* control_;
  const std::string* stage_;
  std::size_t from_, to_;
  std::shared_ptr<std::size_t> selected_ = std::make_shared<std::size_t>(0);
};

// Sharp features (sharpness.hpp) survive decimation as polylines of fewer vertices: a
// collapse next to a crease keeps the vertex on it where it is; a collapse between two vertices
// on creases is allowed only along a crease edge, removing a vertex inside its crease (two
// crease edges, not a corner), whose neighbour along the crease is then joined to the kept one.
// So each crease keeps its ends and corners, no two creases merge, and a flat face between
// creases shrinks to the few triangles it needs (a CAD part's vertices all lie on its edges).
class Creases {
 public:
  using Vertex = SurfaceMesh::Vertex_index;
  Creases(const TriangleMeshData& mesh, std::size_t vertices) : along_(vertices), pinned_(vertices, 0) {
    for (const SharpEdge& e : mesh.sharp.edges) {
      if (e.sharpness <= 0.0f) continue;
      along_[static_cast<std::size_t>(e.a)].push_back({Vertex(static_cast<SurfaceMesh::size_type>(e.b)), e.sharpness});
      along_[static_cast<std::size_t>(e.b)].push_back({Vertex(static_cast<SurfaceMesh::size_type>(e.a)), e.sharpness});
    }
    for (const SharpVertex& v : mesh.sharp.vertices)
      if (v.sharpness > 0.0f) pinned_[static_cast<std::size_t>(v.v)] = 1;
    // Corners, crossings and the ends of darts stay.
    for (std::size_t v = 0; v < vertices; ++v)
      if (!along_[v].empty() && along_[v].size() != 2) pinned_[v] = 1;
  }
  bool on_crease(Vertex v) const { return !along_[v].empty(); }
  bool removable(Vertex v) const { return along_[v].size() == 2 && !pinned_[v]; }
  bool crease_edge(Vertex a, Vertex b) const {
    for (const auto& [w, s] : along_[a])
      if (w == b) return true;
    return false;
  }
  // After the collapse of (v0, v1) into `kept`: its creases are both ends' less each other.
  void collapsed(Vertex v0, Vertex v1, Vertex kept) {
    std::vector<std::pair<Vertex, float>> joined;
    for (const Vertex v : {v0, v1})
      for (const auto& entry : along_[v])
        if (entry.first != v0 && entry.first != v1) joined.push_back(entry);
    const Vertex gone = kept == v0 ? v1 : v0;
    for (const auto& [w, s] : joined)
      for (auto& entry : along_[w])
        if (entry.first == gone) entry.first = kept;
    pinned_[kept] = pinned_[v0] || pinned_[v1];
    along_[gone].clear();
    along_[kept] = std::move(joined);
  }
  // The features of the decimated mesh, its vertices numbered by `index`.
  SharpFeatures features(const std::vector<std::int64_t>& index, const SharpFeatures& given) const {
    SharpFeatures out;
    out.method = given.method;
    for (std::size_t v = 0; v < along_.size(); ++v)
      for (const auto& [w, s] : along_[v])
        if (v < w && index[v] >= 0 && index[w] >= 0)
          out.edges.push_back({static_cast<std::int32_t>(index[v]), static_cast<std::int32_t>(index[w]), s});
    for (const SharpVertex& v : given.vertices)
      if (index[static_cast<std::size_t>(v.v)] >= 0)
        out.vertices.push_back({static_cast<std::int32_t>(index[static_cast<std::size_t>(v.v)]), v.sharpness});
    return out;
  }

 private:
  std::vector<std::vector<std::pair<Vertex, float>>> along_;  // per vertex: its crease neighbours
  std::vector<char> pinned_;
};

// The quadric placement, where no crease is in the way; else the crease vertex's own place, or
// no collapse (CGAL then leaves the edge alone).
template <class Base>
class CreasePlacement {
 public:
  CreasePlacement(const Creases& creases, const Base& base) : creases_(&creases), base_(base) {}
  template <class Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p) const {
    const bool c0 = creases_->on_crease(p.v0()), c1 = creases_->on_crease(p.v1());
    if (!c0 && !c1) return base_(p);
    const auto at = [&p](SurfaceMesh::Vertex_index v) { return get(p.vertex_point_map(), v); };
    if (c0 != c1) return at(c0 ? p.v0() : p.v1());
    if (!creases_->crease_edge(p.v0(), p.v1())) return boost::none;
    if (creases_->removable(p.v0())) return at(p.v1());
    if (creases_->removable(p.v1())) return at(p.v0());
    return boost::none;
  }

 private:
  const Creases* creases_;
  Base base_;
};

// The control visitor, keeping the creases up to date.
class CreaseVisitor : public ControlVisitor {
 public:
  CreaseVisitor(const ControlVisitor& control, Creases& creases) : ControlVisitor(control), creases_(&creases) {}
  void OnCollapsed(const Profile& p, const SurfaceMesh::Vertex_index& kept) { creases_->collapsed(p.v0(), p.v1(), kept); }

 private:
  Creases* creases_;
};

TriangleMeshData collapse_to(const TriangleMeshData& mesh, std::size_t faces, const StageControl& control,
                             const std::string& stage) {
  SurfaceMesh sm = to_surface_mesh(mesh);
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> quadrics(sm);
  const ControlVisitor visitor(control, stage, mesh.triangles.size(), faces);
  if (mesh.sharp.empty()) {
    SMS::edge_collapse(sm, FaceCountReached(sm, faces),
                       CGAL::parameters::get_cost(quadrics.get_cost())
                           .get_placement(quadrics.get_placement())
                           .filter(SMS::Bounded_normal_change_filter<>())
                           .visitor(visitor));
    return prepare_triangle_mesh(to_soup(sm));
  }
  Creases creases(mesh, mesh.points.size());
  SMS::edge_collapse(
      sm, FaceCountReached(sm, faces),
      CGAL::parameters::get_cost(quadrics.get_cost())
          .get_placement(CreasePlacement<std::decay_t<decltype(quadrics.get_placement())>>(creases, quadrics.get_placement()))
          .filter(SMS::Bounded_normal_change_filter<>())
          .visitor(CreaseVisitor(visitor, creases)));
  std::vector<std::int64_t> index;
  PolygonSoup soup = to_soup(sm, &index);
  soup.sharp = creases.features(index, mesh.sharp);
  return prepare_triangle_mesh(soup);
}

// Why `result` is not a valid base with the topology `expected` ("" if it is).
std::string problem_with(const TriangleMeshData& result, const Topology& expected) {
  try {
    const Topology found = topology_of(result);
    if (found != expected)
      return "the topology changed from " + to_string(expected) + " to " + to_string(found);
    return "";
  } catch (const InputError& e) {
    return e.what();
  }
}

}  // namespace

TriangleMeshData decimate(const TriangleMeshData& mesh, std::size_t faces, const std::string& name,
                          const StageControl& control) {
  const std::string stage = "decimating " + name + " to " + with_thousands(faces) + " faces: ";
  const std::string step_stage = stage.substr(0, stage.size() - 2);
  Topology topology;
  try {
    topology = topology_of(mesh);
  } catch (const InputError& e) {
    throw InputError(stage + e.what());
  }
  TriangleMeshData result;
  if (mesh.triangles.size() <= faces) {
    result.points = mesh.points;
    result.triangles = mesh.triangles;
    result.sharp = mesh.sharp;
    result.notes.push_back(name + " has " + with_thousands(mesh.triangles.size()) +
                           " faces, no more than the " + with_thousands(faces) +
                           " asked for: it is used as it is");
    return result;
  }
  // CGAL's checks make a bad result unexpected; should one appear anyway, the same collapse
  // sequence stopped earlier is tried (each time at twice the face count), up to the input
  // itself, so that the base is the smallest valid mesh found.
  std::vector<std::string> notes;
  for (std::size_t goal = faces;; goal *= 2) {
    if (goal >= mesh.triangles.size()) {
      result.points = mesh.points;
      result.triangles = mesh.triangles;
      result.sharp = mesh.sharp;
      notes.push_back("no valid decimation found: " + name + " is used as it is (" +
                      with_thousands(mesh.triangles.size()) + " faces)");
      break;
    }
    std::string problem;
    try {
      result = collapse_to(mesh, goal, control, step_stage);
      problem = problem_with(result, topology);
    } catch (const InputError& e) {
      problem = e.what();
    }
    if (problem.empty()) break;
    notes.push_back("the decimation to " + with_thousands(goal) + " faces gave an invalid mesh (" + problem +
                    "): trying fewer collapses");
  }
  if (notes.empty() && result.triangles.size() > faces + 1)
    notes.push_back("could only decimate to " + with_thousands(result.triangles.size()) + " faces (" +
                    with_thousands(faces) +
                    " asked for): further edge collapses would change the topology (" + to_string(topology) +
                    ") or fold triangles");
  notes.insert(notes.begin(), result.notes.begin(), result.notes.end());
  result.notes = std::move(notes);
  return result;
}

}  // namespace rgbmesh::fit
