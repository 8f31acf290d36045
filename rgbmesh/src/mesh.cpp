// RGB triangulation: construction, navigation, the local operators of section IV and their
// composition into split_edge / remove_vertex (section V).

#include "rgbmesh/mesh.hpp"

#include <algorithm>
#include <cstring>
#include <cassert>
#include <sstream>
#include <unordered_map>

#include "rgbmesh/soup.hpp"

namespace rgbmesh {

namespace {

std::uint64_t pair_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

char color_letter(Color c) {
  switch (c) {
    case Color::green:
      return 'G';
    case Color::red:
      return 'R';
    case Color::blue:
      return 'B';
  }
  return '?';
}

}  // namespace

const char* to_string(SplitKind k) {
  switch (k) {
    case SplitKind::not_refinable:
      return "not refinable";
    case SplitKind::gg:
      return "GG-split";
    case SplitKind::rg:
      return "RG-split";
    case SplitKind::rr1:
      return "RR1-split";
    case SplitKind::rr2:
      return "RR2-split";
    case SplitKind::g_boundary:
      return "G-boundary-split";
    case SplitKind::r_boundary:
      return "R-boundary-split";
  }
  return "?";
}

const char* to_string(MergeKind k) {
  switch (k) {
    case MergeKind::not_mergeable:
      return "not mergeable";
    case MergeKind::r4:
      return "R4-merge";
    case MergeKind::r2gb:
      return "R2GB-merge";
    case MergeKind::gbgb:
      return "GBGB-merge";
    case MergeKind::g2b2:
      return "G2B2-merge";
    case MergeKind::r2_boundary:
      return "R2-boundary-merge";
    case MergeKind::gb_boundary:
      return "GB-boundary-merge";
  }
  return "?";
}

// ---------------------------------------------------------------------------------------
// Copying: topology, geometry and property values; observers belong to the original.

RgbMesh::RgbMesh(const RgbMesh& o)
    : v_edge_(o.v_edge_),
      v_level_(o.v_level_),
      v_parents_(o.v_parents_),
      v_control_(o.v_control_),
      v_limit_index_(o.v_limit_index_),
      limits_(o.limits_),
      limits_free_(o.limits_free_),
      v_flags_(o.v_flags_),
      base_eigenvalue_(o.base_eigenvalue_),
      v_free_(o.v_free_),
      e_vert_(o.e_vert_),
      e_tri_(o.e_tri_),
      e_info_(o.e_info_),
      e_free_(o.e_free_),
      t_edge_(o.t_edge_),
      t_info_(o.t_info_),
      t_free_(o.t_free_),
      n_vertices_(o.n_vertices_),
      n_edges_(o.n_edges_),
      n_triangles_(o.n_triangles_),
      n_base_vertices_(o.n_base_vertices_),
      base_euler_(o.base_euler_),
      counters_(o.counters_) {
  for (const auto& p : o.vertex_properties_) vertex_properties_.push_back(p->clone());
}

RgbMesh& RgbMesh::operator=(const RgbMesh& o) {
  if (this != &o) {
    RgbMesh copy(o);
    *this = std::move(copy);
  }
  return *this;
}

// ---------------------------------------------------------------------------------------
// Construction

RgbMesh RgbMesh::from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles) {
  RgbMesh m;
  const auto nv = static_cast<std::int32_t>(points.size());
  if (nv == 0 || triangles.empty()) throw InputError("the mesh is empty");
  m.v_edge_.assign(nv, EdgeHandle());
  m.v_level_.assign(nv, 0);
  m.v_parents_.assign(nv, {VertexHandle(), VertexHandle()});
  m.v_control_ = points;
  m.n_vertices_ = static_cast<std::size_t>(nv);
  m.n_base_vertices_ = m.n_vertices_;

  std::unordered_map<std::uint64_t, EdgeHandle> edge_of;
  edge_of.reserve(triangles.size() * 2);
  m.t_edge_.reserve(triangles.size());
  m.t_info_.reserve(triangles.size());
  for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
    const auto& tri = triangles[ti];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= nv)
        throw InputError("triangle " + std::to_string(ti) + " references vertex " + std::to_string(tri[k]) +
                         " out of range");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      throw InputError("triangle " + std::to_string(ti) + " is degenerate");
    const TriangleHandle t(static_cast<std::int32_t>(ti));
    std::array<EdgeHandle, 3> te;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
      auto [it, inserted] = edge_of.try_emplace(pair_key(a, b), EdgeHandle());
      if (inserted) {
        const EdgeHandle e(static_cast<std::int32_t>(m.e_vert_.size()));
        m.e_vert_.push_back({VertexHandle(a), VertexHandle(b)});
        m.e_tri_.push_back({t, TriangleHandle()});
        m.e_info_.push_back(edge_info(false, 0));
        it->second = e;
        m.v_edge_[a] = e;
        m.v_edge_[b] = e;
      } else {
        const EdgeHandle e = it->second;
        auto& et = m.e_tri_[e.idx];
        // The second triangle of an edge must traverse it in the opposite direction.
        if (et[1].valid())
          throw InputError("edge (" + std::to_string(a) + ", " + std::to_string(b) +
                           ") is shared by more than two triangles");
        if (m.e_vert_[e.idx][0].idx != b)
          throw InputError("triangle " + std::to_string(ti) +
                           " is oriented inconsistently with its neighbour across edge (" +
                           std::to_string(a) + ", " + std::to_string(b) + ")");
        et[1] = t;
      }
      te[k] = it->second;
    }
    m.t_edge_.push_back(te);
    m.t_info_.push_back(0);  // green, level 0
  }
  m.n_edges_ = m.e_vert_.size();
  m.n_triangles_ = m.t_edge_.size();
  for (std::int32_t v = 0; v < nv; ++v) {
    if (!m.v_edge_[v].valid())
      throw InputError("vertex " + std::to_string(v) + " is not referenced by any triangle");
  }
  // Manifold vertices: the fan reached from the stored edge must cover every incident edge.
  std::vector<int> degree(nv, 0);
  for (const auto& ev : m.e_vert_) {
    ++degree[ev[0].idx];
    ++degree[ev[1].idx];
  }
  VertexStar s;
  for (std::int32_t v = 0; v < nv; ++v) {
    m.star(VertexHandle(v), s);
    if (static_cast<int>(s.edges.size()) != degree[v])
      throw InputError("vertex " + std::to_string(v) + " is non-manifold");
  }
  m.base_euler_ = m.euler_characteristic();
  m.init_base_geometry();
  return m;
}

// ---------------------------------------------------------------------------------------
// Allocation

void RgbMesh::reserve(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  if (vertices > v_edge_.capacity()) {
    v_edge_.reserve(vertices);
    v_level_.reserve(vertices);
    v_parents_.reserve(vertices);
    v_control_.reserve(vertices);
    v_limit_index_.reserve(vertices);
    v_flags_.reserve(vertices);
  }
  if (edges > e_vert_.capacity()) {
    e_vert_.reserve(edges);
    e_tri_.reserve(edges);
    e_info_.reserve(edges);
  }
  if (triangles > t_edge_.capacity()) {
    t_edge_.reserve(triangles);
    t_info_.reserve(triangles);
  }
}

std::size_t RgbMesh::memory_bytes() const {
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(v_edge_) + bytes(v_level_) + bytes(v_parents_) + bytes(v_control_) + bytes(v_limit_index_) +
         bytes(limits_) + bytes(limits_free_) + bytes(v_flags_) + bytes(v_free_) + bytes(e_vert_) + bytes(e_tri_) +
         bytes(e_info_) + bytes(e_free_) + bytes(t_edge_) + bytes(t_info_) + bytes(t_free_) + bytes(base_eigenvalue_);
}

std::size_t RgbMesh::storage_bytes(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  // Per vertex: its arrays, plus a limit position for about a quarter of them (the side table).
  const std::size_t vertex = sizeof(EdgeHandle) + sizeof(std::uint8_t) + sizeof(std::array<VertexHandle, 2>) +
                             sizeof(Vec3) + sizeof(std::int32_t) + sizeof(std::uint8_t) + sizeof(Vec3) / 4;
  const std::size_t edge = sizeof(std::array<VertexHandle, 2>) + sizeof(std::array<TriangleHandle, 2>) + 1;
  const std::size_t triangle = sizeof(std::array<EdgeHandle, 3>) + 1;
  return vertices * vertex + edges * edge + triangles * triangle;
}

VertexHandle RgbMesh::new_vertex() {
  VertexHandle v;
  if (!v_free_.empty()) {
    v = VertexHandle(v_free_.back());
    v_free_.pop_back();
  } else {
    v = VertexHandle(static_cast<std::int32_t>(v_edge_.size()));
    v_edge_.emplace_back();
    v_level_.push_back(0);
    v_parents_.push_back({VertexHandle(), VertexHandle()});
    v_control_.emplace_back();
    v_limit_index_.push_back(-1);
    v_flags_.push_back(0);
    for (auto& p : vertex_properties_) p->resize(v_edge_.size());
  }
  ++n_vertices_;
  return v;
}

EdgeHandle RgbMesh::new_edge(VertexHandle a, VertexHandle b, std::uint8_t info) {
  EdgeHandle e;
  if (!e_free_.empty()) {
    e = EdgeHandle(e_free_.back());
    e_free_.pop_back();
    e_vert_[e.idx] = {a, b};
    e_tri_[e.idx] = {TriangleHandle(), TriangleHandle()};
    e_info_[e.idx] = info;
  } else {
    e = EdgeHandle(static_cast<std::int32_t>(e_vert_.size()));
    e_vert_.push_back({a, b});
    e_tri_.push_back({TriangleHandle(), TriangleHandle()});
    e_info_.push_back(info);
  }
  ++n_edges_;
  return e;
}

TriangleHandle RgbMesh::new_triangle(const std::array<EdgeHandle, 3>& edges) {
  TriangleHandle t;
  if (!t_free_.empty()) {
    t = TriangleHandle(t_free_.back());
    t_free_.pop_back();
    t_edge_[t.idx] = edges;
  } else {
    t = TriangleHandle(static_cast<std::int32_t>(t_edge_.size()));
    t_edge_.push_back(edges);
    t_info_.push_back(0);
  }
  ++n_triangles_;
  return t;
}

void RgbMesh::free_vertex(VertexHandle v) {
  v_edge_[v.idx] = EdgeHandle();
  v_parents_[v.idx] = {VertexHandle(), VertexHandle()};
  v_flags_[v.idx] = 0;
  release_limit(v);
  v_free_.push_back(v.idx);
  --n_vertices_;
}

void RgbMesh::free_edge(EdgeHandle e) {
  e_vert_[e.idx] = {VertexHandle(), VertexHandle()};
  e_tri_[e.idx] = {TriangleHandle(), TriangleHandle()};
  e_free_.push_back(e.idx);
  --n_edges_;
}

void RgbMesh::free_triangle(TriangleHandle t) {
  t_edge_[t.idx] = {EdgeHandle(), EdgeHandle(), EdgeHandle()};
  t_free_.push_back(t.idx);
  --n_triangles_;
}

// ---------------------------------------------------------------------------------------
// Navigation

HandleRange<VertexHandle> RgbMesh::vertices() const {
  return {*this, vertex_slots(), [](const RgbMesh& m, std::int32_t i) { return m.v_edge_[i].valid(); }};
}
HandleRange<EdgeHandle> RgbMesh::edges() const {
  return {*this, edge_slots(), [](const RgbMesh& m, std::int32_t i) { return m.e_vert_[i][0].valid(); }};
}
HandleRange<TriangleHandle> RgbMesh::triangles() const {
  return {*this, triangle_slots(), [](const RgbMesh& m, std::int32_t i) { return m.t_edge_[i][0].valid(); }};
}

std::array<VertexHandle, 3> RgbMesh::triangle_vertices(TriangleHandle t) const {
  const auto& te = t_edge_[t.idx];
  const auto& a = e_vert_[te[0].idx];
  const auto& b = e_vert_[te[1].idx];
  // Corner 1 is shared by edges 0 and 1; corners 0 and 2 are their other ends.
  const VertexHandle c1 = (a[0] == b[0] || a[0] == b[1]) ? a[0] : a[1];
  const VertexHandle c0 = (c1 == a[0]) ? a[1] : a[0];
  const VertexHandle c2 = (c1 == b[0]) ? b[1] : b[0];
  return {c0, c1, c2};
}

int RgbMesh::local_index(TriangleHandle t, EdgeHandle e) const {
  const auto& te = t_edge_[t.idx];
  return te[0] == e ? 0 : (te[1] == e ? 1 : (te[2] == e ? 2 : -1));
}

VertexHandle RgbMesh::opposite_vertex(TriangleHandle t, EdgeHandle e) const {
  const int i = local_index(t, e);
  assert(i >= 0);
  // The far end of the next edge: the endpoint it does not share with e.
  const auto& n = e_vert_[t_edge_[t.idx][(i + 1) % 3].idx];
  const auto& ev = e_vert_[e.idx];
  return (n[0] == ev[0] || n[0] == ev[1]) ? n[1] : n[0];
}

void RgbMesh::replace_edge_triangle(EdgeHandle e, TriangleHandle from, TriangleHandle to) {
  auto& et = e_tri_[e.idx];
  if (et[0] == from) {
    et[0] = to;
  } else {
    assert(et[1] == from);
    et[1] = to;
  }
}

// Rotation around a vertex. In a triangle with v at corner i, edge i leaves v and edge i+2
// arrives at v; going counter-clockwise around v, the leaving edge comes first, and the next
// triangle counter-clockwise is the one beyond the arriving edge. Whether e leaves or arrives
// at v in t is read off the neighbouring edge of t: no corner computation needed.

// The triangle in which e leaves v, and that triangle's edge arriving at v.
std::pair<TriangleHandle, EdgeHandle> RgbMesh::leaving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle prev = te[(i + 2) % 3];
    if (e_vert_[prev.idx][0] == v || e_vert_[prev.idx][1] == v) return {t, prev};
  }
  return {TriangleHandle(), EdgeHandle()};
}

// The triangle in which e arrives at v, and that triangle's edge leaving v.
std::pair<TriangleHandle, EdgeHandle> RgbMesh::arriving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle next = te[(i + 1) % 3];
    if (e_vert_[next.idx][0] == v || e_vert_[next.idx][1] == v) return {t, next};
  }
  return {TriangleHandle(), EdgeHandle()};
}

void RgbMesh::star(VertexHandle v, VertexStar& out) const {
  // A corrupted structure must not loop forever (validate() relies on this).
  const std::size_t guard = n_edges_ + 1;
  auto collect_from = [&](EdgeHandle first) {
    out.edges.clear();
    out.neighbors.clear();
    out.triangles.clear();
    EdgeHandle e = first;
    for (std::size_t step = 0; step < guard; ++step) {
      out.edges.push_back(e);
      out.neighbors.push_back(other_vertex(e, v));
      const auto [t, next] = leaving_triangle(v, e);
      if (!t.valid()) return false;  // hit the boundary
      out.triangles.push_back(t);
      e = next;
      if (e == first) return true;  // closed the cycle
    }
    return true;
  };
  out.boundary = false;
  const EdgeHandle start = v_edge_[v.idx];
  if (collect_from(start)) return;
  // A boundary vertex: walk clockwise to the boundary edge where the fan starts.
  out.boundary = true;
  EdgeHandle first = start;
  for (std::size_t step = 0; step < guard; ++step) {
    const auto [t, prev] = arriving_triangle(v, first);
    if (!t.valid()) break;
    first = prev;
  }
  collect_from(first);
}

bool RgbMesh::is_boundary(VertexHandle v) const {
  bool boundary = false;
  visit_edges(v, [&](EdgeHandle e) {
    boundary = boundary || is_boundary(e);
    return !boundary;
  });
  return boundary;
}

int RgbMesh::valence(VertexHandle v) const {
  int n = 0;
  visit_edges(v, [&](EdgeHandle) {
    ++n;
    return true;
  });
  return n;
}

EdgeHandle RgbMesh::find_edge(VertexHandle a, VertexHandle b) const {
  EdgeHandle found;
  visit_edges(a, [&](EdgeHandle e) {
    if (other_vertex(e, a) == b) found = e;
    return !found.valid();
  });
  return found;
}

int RgbMesh::max_level() const {
  int l = 0;
  for (VertexHandle v : vertices()) l = std::max(l, level(v));
  return l;
}

int RgbMesh::boundary_loops() const {
  // Boundary edges, chained head to tail through their vertices.
  std::unordered_map<std::int32_t, std::int32_t> next_of;  // start vertex -> boundary edge
  std::vector<EdgeHandle> boundary;
  for (EdgeHandle e : edges()) {
    if (!is_boundary(e)) continue;
    boundary.push_back(e);
  }
  std::unordered_map<std::int32_t, std::vector<std::int32_t>> at_vertex;
  for (EdgeHandle e : boundary) {
    at_vertex[e_vert_[e.idx][0].idx].push_back(e.idx);
    at_vertex[e_vert_[e.idx][1].idx].push_back(e.idx);
  }
  std::unordered_map<std::int32_t, bool> seen;
  int loops = 0;
  for (EdgeHandle e0 : boundary) {
    if (seen[e0.idx]) continue;
    ++loops;
    std::vector<std::int32_t> stack{e0.idx};
    while (!stack.empty()) {
      const std::int32_t e = stack.back();
      stack.pop_back();
      if (seen[e]) continue;
      seen[e] = true;
      for (VertexHandle v : e_vert_[e]) {
        for (std::int32_t f : at_vertex[v.idx]) {
          if (!seen[f]) stack.push_back(f);
        }
      }
    }
  }
  return loops;
}

// ---------------------------------------------------------------------------------------
// Attributes and predicates

void RgbMesh::update_triangle_info(TriangleHandle t) {
  const auto& te = t_edge_[t.idx];
  const int l0 = level(te[0]), l1 = level(te[1]), l2 = level(te[2]);
  const int lo = std::min({l0, l1, l2});
  // Green: all edges at one level; red: one edge a level finer; blue: two (section IV-A).
  const int finer = (l0 > lo) + (l1 > lo) + (l2 > lo);
  t_info_[t.idx] = static_cast<std::uint8_t>((finer << 6) | lo);
}

void RgbMesh::raising_edges(TriangleHandle t, std::vector<EdgeHandle>& out) const {
  out.clear();
  const int l = level(t);
  TriangleHandle source = t;
  if (color(t) == Color::blue) {
    // A blue triangle rises when its red sibling splits its coarse edge and the pair is
    // BB-swapped (section V-B).
    for (EdgeHandle f : triangle_edges(t)) {
      if (is_red(f)) source = other_triangle(f, t);
    }
    if (!source.valid() || color(source) != Color::red || level(source) != l) return;
  }
  for (EdgeHandle f : triangle_edges(source)) {
    if (!is_red(f) && level(f) == l) out.push_back(f);
  }
}

bool RgbMesh::is_refinable(EdgeHandle e) const {
  if (is_red(e)) return false;
  const int l = level(e);
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (t.valid() && level(t) != l) return false;
  }
  return l < kMaxLevel;
}

bool RgbMesh::is_removable(VertexHandle v) const {
  const int l = level(v);
  if (l == 0) return false;
  bool removable = true;
  visit_edges(v, [&](EdgeHandle e) {
    removable = level(other_vertex(e, v)) <= l;
    return removable;
  });
  return removable;
}

bool RgbMesh::is_stable() const {
  for (EdgeHandle e : edges()) {
    if (!is_red(e)) continue;
    const auto& et = e_tri_[e.idx];
    if (et[1].valid() && color(et[0]) == Color::blue && color(et[1]) == Color::blue) return false;
  }
  return true;
}

SplitKind RgbMesh::split_kind(EdgeHandle e) const {
  if (!alive(e) || !is_refinable(e)) return SplitKind::not_refinable;
  const auto& et = e_tri_[e.idx];
  if (!et[1].valid()) {
    return color(et[0]) == Color::green ? SplitKind::g_boundary : SplitKind::r_boundary;
  }
  const Color c0 = color(et[0]), c1 = color(et[1]);
  if (c0 == Color::green && c1 == Color::green) return SplitKind::gg;
  if (c0 == Color::green || c1 == Color::green) return SplitKind::rg;
  // Both red: RR1 when the two red edges end at different endpoints of e (the diamond's
  // boundary alternates red-green-red-green), RR2 when they share one (Fig. 5).
  auto red_end = [&](TriangleHandle t) {
    for (EdgeHandle f : t_edge_[t.idx]) {
      if (is_red(f)) {
        const auto& fv = e_vert_[f.idx];
        const auto& ev = e_vert_[e.idx];
        return (fv[0] == ev[0] || fv[1] == ev[0]) ? ev[0] : ev[1];
      }
    }
    return VertexHandle();
  };
  return red_end(et[0]) == red_end(et[1]) ? SplitKind::rr2 : SplitKind::rr1;
}

std::string RgbMesh::describe(EdgeHandle e) const {
  std::ostringstream s;
  s << "edge " << e.idx;
  if (alive(e)) {
    s << " (" << e_vert_[e.idx][0].idx << ", " << e_vert_[e.idx][1].idx << "; "
      << (is_red(e) ? "red" : "green") << ", level " << level(e) << ")";
  } else {
    s << " (not alive)";
  }
  return s.str();
}

std::string RgbMesh::describe(VertexHandle v) const {
  std::ostringstream s;
  s << "vertex " << v.idx;
  if (alive(v)) {
    s << " (level " << level(v) << ")";
  } else {
    s << " (not alive)";
  }
  return s.str();
}

void RgbMesh::fail(const char* op, const std::string& what) const {
  throw PreconditionError(std::string(op) + ": " + what);
}

// ---------------------------------------------------------------------------------------
// Topological primitives

// Inserts a vertex m at the midpoint of e = (v0, v1) and bisects each incident triangle
// (a, b, c) into (a, m, c) and (m, b, c) through a new edge (m, c). The halves of e are green
// one level finer; the bisecting edge is red at e's level in a green triangle and green one
// level finer in a red triangle (section IV-A).
VertexHandle RgbMesh::bisect(EdgeHandle e, const Vec3& control) {
  const auto [v0, v1] = e_vert_[e.idx];
  const int l = level(e);
  const bool boundary = is_boundary(e);
  struct Side {
    int slot;
    TriangleHandle t;
    VertexHandle a, c;
    EdgeHandle eb, ec;  // (b, c) and (c, a)
    bool red;
  };
  Side sides[2];
  int n = 0;
  for (int k = 0; k < 2; ++k) {
    const TriangleHandle t = e_tri_[e.idx][k];
    if (!t.valid()) continue;
    const int i = local_index(t, e);
    const auto c = triangle_vertices(t);
    sides[n++] = Side{k,
                      t,
                      c[i],
                      c[(i + 2) % 3],
                      t_edge_[t.idx][(i + 1) % 3],
                      t_edge_[t.idx][(i + 2) % 3],
                      color(t) == Color::red};
  }

  const VertexHandle m = new_vertex();
  v_level_[m.idx] = static_cast<std::uint8_t>(l + 1);
  v_parents_[m.idx] = {v0, v1};
  v_control_[m.idx] = control;
  v_flags_[m.idx] = boundary ? kBoundaryFlag : 0;

  const std::uint8_t half_info = edge_info(false, l + 1);
  const EdgeHandle e1 = new_edge(m, v1, half_info);  // e keeps (v0, m)
  e_vert_[e.idx] = {v0, m};
  e_info_[e.idx] = half_info;
  if (v_edge_[v1.idx] == e) v_edge_[v1.idx] = e1;
  v_edge_[m.idx] = e;

  for (int s = 0; s < n; ++s) {
    const Side& sd = sides[s];
    const EdgeHandle ha = (sd.a == v0) ? e : e1;  // the half at a
    const EdgeHandle hb = (ha == e) ? e1 : e;     // the half at b
    const EdgeHandle mc = new_edge(m, sd.c, sd.red ? edge_info(false, l + 1) : edge_info(true, l));
    const TriangleHandle tb = new_triangle({hb, sd.eb, mc});  // (m, b, c)
    t_edge_[sd.t.idx] = {ha, mc, sd.ec};                      // (a, m, c)
    e_tri_[mc.idx] = {sd.t, tb};
    replace_edge_triangle(sd.eb, sd.t, tb);
    e_tri_[ha.idx][sd.slot] = sd.t;
    e_tri_[hb.idx][sd.slot] = tb;
    update_triangle_info(sd.t);
    update_triangle_info(tb);
  }
  ++counters_.splits;
  if (journal_) journal_->push_back({JournalEntry::bisect, m.idx, 0});
  return m;
}

// Replaces the diagonal e of the quadrilateral formed by its two triangles with the other
// diagonal. t0 = (a, b, c) and t1 = (b, a, d) become (d, b, c) and (c, a, d).
void RgbMesh::flip(EdgeHandle e, std::uint8_t new_info) {
  if (journal_) journal_->push_back({JournalEntry::flip, e.idx, e_info_[e.idx]});
  const TriangleHandle t0 = e_tri_[e.idx][0], t1 = e_tri_[e.idx][1];
  const int i = local_index(t0, e), j = local_index(t1, e);
  const auto c0 = triangle_vertices(t0), c1 = triangle_vertices(t1);
  const VertexHandle a = c0[i], b = c0[(i + 1) % 3], c = c0[(i + 2) % 3];
  const VertexHandle d = c1[(j + 2) % 3];
  const EdgeHandle bc = t_edge_[t0.idx][(i + 1) % 3], ca = t_edge_[t0.idx][(i + 2) % 3];
  const EdgeHandle ad = t_edge_[t1.idx][(j + 1) % 3], db = t_edge_[t1.idx][(j + 2) % 3];
  t_edge_[t0.idx] = {db, bc, e};
  t_edge_[t1.idx] = {ca, ad, e};
  e_vert_[e.idx] = {c, d};
  e_info_[e.idx] = new_info;
  replace_edge_triangle(ca, t0, t1);
  replace_edge_triangle(db, t1, t0);
  if (v_edge_[a.idx] == e) v_edge_[a.idx] = ca;
  if (v_edge_[b.idx] == e) v_edge_[b.idx] = bc;
  update_triangle_info(t0);
  update_triangle_info(t1);
}

// Inverse of bisect: m (valence 4, or 3 on the boundary) with parents a, b is removed; its
// halves (a, m), (m, b) become the edge (a, b) again, green at level(m) - 1, and on each side
// the two triangles (a, m, c), (m, b, c) become (a, b, c).
EdgeHandle RgbMesh::unbisect(VertexHandle m) {
  const auto [a, b] = v_parents_[m.idx];
  return unbisect(m, find_edge(m, a), find_edge(m, b));
}

EdgeHandle RgbMesh::unbisect(VertexHandle m, EdgeHandle ea, EdgeHandle eb) {
  const auto [a, b] = v_parents_[m.idx];
  for (int k = 0; k < 2; ++k) {
    const TriangleHandle ta = e_tri_[ea.idx][k];
    if (!ta.valid()) continue;
    // ta holds ea, (m, c) and (c, a); its neighbour across (m, c) holds eb and (b, c).
    const int ia = local_index(ta, ea);
    const auto& te = t_edge_[ta.idx];
    const EdgeHandle e_next = te[(ia + 1) % 3], e_prev = te[(ia + 2) % 3];
    const auto& nv = e_vert_[e_next.idx];
    const bool next_is_mc = (nv[0] == m || nv[1] == m);
    const EdgeHandle mc = next_is_mc ? e_next : e_prev;
    const int imc = next_is_mc ? (ia + 1) % 3 : (ia + 2) % 3;
    const TriangleHandle tb = other_triangle(mc, ta);
    const int ib = local_index(tb, eb);
    const auto& tbe = t_edge_[tb.idx];
    const EdgeHandle f1 = tbe[(ib + 1) % 3], f2 = tbe[(ib + 2) % 3];
    const EdgeHandle bc = (f1 == mc) ? f2 : f1;
    const VertexHandle c = other_vertex(mc, m);
    t_edge_[ta.idx][imc] = bc;
    replace_edge_triangle(bc, tb, ta);
    if (v_edge_[c.idx] == mc) v_edge_[c.idx] = (next_is_mc ? e_prev : e_next);
    free_triangle(tb);
    free_edge(mc);
  }
  if (v_edge_[b.idx] == eb) v_edge_[b.idx] = ea;
  e_vert_[ea.idx] = {a, b};
  e_info_[ea.idx] = edge_info(false, level(m) - 1);
  free_edge(eb);
  for (TriangleHandle t : e_tri_[ea.idx]) {
    if (t.valid()) update_triangle_info(t);
  }
  free_vertex(m);
  ++counters_.removals;
  return ea;
}

// ---------------------------------------------------------------------------------------
// Splits (Fig. 5)

VertexHandle RgbMesh::checked_split(EdgeHandle e, SplitKind kind, const char* op) {
  if (!alive(e)) fail(op, describe(e) + " does not exist");
  const SplitKind actual = split_kind(e);
  if (actual != kind)
    fail(op, describe(e) + " is " +
                 (actual == SplitKind::not_refinable ? std::string("not refinable")
                                                     : std::string("a case for ") + to_string(actual)));
  return split_checked_edge(e, kind, op);
}

VertexHandle RgbMesh::split_checked_edge(EdgeHandle e, SplitKind kind, const char* op) {
  // The stencil's coarser vertices need their limit positions; providing them may insert
  // vertices around them, never touching e's triangles, which are finer (section VI-C).
  const std::array<VertexHandle, 4> st = stencil(e);
  if (prepare_stencil(st, level(e)) && split_kind(e) != kind)
    fail(op, "internal error: preparing the stencil changed " + describe(e));
  const VertexHandle m = bisect(e, stencil_point(st, level(e)));
  notify_inserted(m);
  return m;
}

VertexHandle RgbMesh::split_gg(EdgeHandle e) { return checked_split(e, SplitKind::gg, "split_gg"); }
VertexHandle RgbMesh::split_rg(EdgeHandle e) { return checked_split(e, SplitKind::rg, "split_rg"); }
VertexHandle RgbMesh::split_rr1(EdgeHandle e) { return checked_split(e, SplitKind::rr1, "split_rr1"); }
VertexHandle RgbMesh::split_rr2(EdgeHandle e) { return checked_split(e, SplitKind::rr2, "split_rr2"); }
VertexHandle RgbMesh::split_g_boundary(EdgeHandle e) {
  return checked_split(e, SplitKind::g_boundary, "split_g_boundary");
}
VertexHandle RgbMesh::split_r_boundary(EdgeHandle e) {
  return checked_split(e, SplitKind::r_boundary, "split_r_boundary");
}

VertexHandle RgbMesh::split_refinable(EdgeHandle e) {
  if (!alive(e)) fail("split_refinable", describe(e) + " does not exist");
  const SplitKind kind = split_kind(e);
  if (kind == SplitKind::not_refinable) fail("split_refinable", describe(e) + " is not refinable");
  return split_checked_edge(e, kind, "split_refinable");
}

void RgbMesh::notify_inserted(VertexHandle v) {
  const auto& p = v_parents_[v.idx];
  for (const auto& o : insertion_observers_) o.cb(v, p[0], p[1]);
}

// ---------------------------------------------------------------------------------------
// Merges (inverse of Fig. 5)

MergeKind RgbMesh::merge_kind(VertexHandle v) const {
  if (!alive(v) || level(v) == 0) return MergeKind::not_mergeable;
  const auto [a, b] = v_parents_[v.idx];
  const int l = level(v) - 1;
  VertexStar& s = scratch_star_;  // reused: no allocation per removal
  star(v, s);
  const std::size_t n = s.edges.size();
  if (n != (s.boundary ? 3u : 4u)) return MergeKind::not_mergeable;
  // Locate the halves of the split edge in the star.
  std::size_t ia = n, ib = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (s.neighbors[i] == a) ia = i;
    if (s.neighbors[i] == b) ib = i;
  }
  if (ia == n || ib == n) return MergeKind::not_mergeable;
  for (std::size_t i : {ia, ib}) {
    if (is_red(s.edges[i]) || level(s.edges[i]) != l + 1) return MergeKind::not_mergeable;
  }
  if (s.boundary && !((ia == 0 && ib == 2) || (ia == 2 && ib == 0))) return MergeKind::not_mergeable;
  if (!s.boundary && (ia + 2) % 4 != ib) return MergeKind::not_mergeable;
  // Each side is the pair of triangles around the middle edge between the halves:
  // G-form (two red triangles on a red edge of level l: the side was a green triangle) or
  // R-form (green + blue on a green edge of level l+1: the side was a red triangle).
  enum SideForm { bad, g_form, r_form };
  struct SideInfo {
    SideForm form;
    VertexHandle green_end;
  };
  auto side = [&](std::size_t mid) -> SideInfo {
    const EdgeHandle me = s.edges[mid];
    const TriangleHandle t0 = s.triangles[(mid + n - 1) % n];  // before the middle edge
    const TriangleHandle t1 = s.triangles[mid % s.triangles.size()];
    const Color c0 = color(t0), c1 = color(t1);
    if (is_red(me) && level(me) == l && c0 == Color::red && c1 == Color::red && level(t0) == l &&
        level(t1) == l)
      return {g_form, VertexHandle()};
    if (!is_red(me) && level(me) == l + 1 && level(s.neighbors[mid]) == l + 1) {
      if (c0 == Color::green && c1 == Color::blue && level(t0) == l + 1 && level(t1) == l)
        return {r_form, s.neighbors[(mid + n - 1) % n]};
      if (c0 == Color::blue && c1 == Color::green && level(t0) == l && level(t1) == l + 1)
        return {r_form, s.neighbors[(mid + 1) % n]};
    }
    return {bad, VertexHandle()};
  };
  if (s.boundary) {
    const SideInfo si = side(1);
    if (si.form == g_form) return MergeKind::r2_boundary;
    if (si.form == r_form) return MergeKind::gb_boundary;
    return MergeKind::not_mergeable;
  }
  const SideInfo s0 = side((ia + 1) % 4), s1 = side((ia + 3) % 4);
  if (s0.form == bad || s1.form == bad) return MergeKind::not_mergeable;
  if (s0.form == g_form && s1.form == g_form) return MergeKind::r4;
  if (s0.form != s1.form) return MergeKind::r2gb;
  // Both sides were red: RR1 when the green triangles sit at different parent endpoints.
  return s0.green_end == s1.green_end ? MergeKind::g2b2 : MergeKind::gbgb;
}

EdgeHandle RgbMesh::checked_merge(VertexHandle v, MergeKind kind, const char* op) {
  if (!alive(v)) fail(op, describe(v) + " does not exist");
  const MergeKind actual = merge_kind(v);
  if (actual != kind)
    fail(op, describe(v) + " is " +
                 (actual == MergeKind::not_mergeable ? std::string("not mergeable")
                                                     : std::string("a case for ") + to_string(actual)));
  for (const auto& o : removal_observers_) o.cb(v);
  return unbisect(v);
}

EdgeHandle RgbMesh::merge_r4(VertexHandle v) { return checked_merge(v, MergeKind::r4, "merge_r4"); }
EdgeHandle RgbMesh::merge_r2gb(VertexHandle v) { return checked_merge(v, MergeKind::r2gb, "merge_r2gb"); }
EdgeHandle RgbMesh::merge_gbgb(VertexHandle v) { return checked_merge(v, MergeKind::gbgb, "merge_gbgb"); }
EdgeHandle RgbMesh::merge_g2b2(VertexHandle v) { return checked_merge(v, MergeKind::g2b2, "merge_g2b2"); }
EdgeHandle RgbMesh::merge_r2_boundary(VertexHandle v) {
  return checked_merge(v, MergeKind::r2_boundary, "merge_r2_boundary");
}
EdgeHandle RgbMesh::merge_gb_boundary(VertexHandle v) {
  return checked_merge(v, MergeKind::gb_boundary, "merge_gb_boundary");
}

EdgeHandle RgbMesh::merge(VertexHandle v) {
  if (!alive(v)) fail("merge", describe(v) + " does not exist");
  const MergeKind kind = merge_kind(v);
  if (kind == MergeKind::not_mergeable) fail("merge", describe(v) + " is not mergeable");
  for (const auto& o : removal_observers_) o.cb(v);
  return unbisect(v);
}

// ---------------------------------------------------------------------------------------
// Swaps (Fig. 6)

EdgeHandle RgbMesh::swap_bb(EdgeHandle e) {
  if (!alive(e)) fail("swap_bb", describe(e) + " does not exist");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  const bool ok = is_red(e) && et[1].valid() && color(et[0]) == Color::blue && color(et[1]) == Color::blue &&
                  level(et[0]) == l && level(et[1]) == l;
  if (!ok) fail("swap_bb", describe(e) + " is not a red edge between two blue triangles of its level");
  // The new diagonal joins two midpoints of level l+1: green, level l+1.
  flip(e, edge_info(false, l + 1));
  ++counters_.swaps_bb;
  return e;
}

EdgeHandle RgbMesh::swap_gg(EdgeHandle e) {
  if (!alive(e)) fail("swap_gg", describe(e) + " does not exist");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  bool ok = !is_red(e) && l > 0 && et[1].valid() && color(et[0]) == Color::green &&
            color(et[1]) == Color::green && level(et[0]) == l && level(et[1]) == l;
  if (ok) {
    // One of the two triangles must be the central child of their common parent: all three
    // vertices at level l (section IV-B). That makes them siblings.
    auto all_at_level = [&](TriangleHandle t) {
      for (VertexHandle v : triangle_vertices(t))
        if (level(v) != l) return false;
      return true;
    };
    ok = all_at_level(et[0]) != all_at_level(et[1]);
  }
  if (!ok)
    fail("swap_gg", describe(e) + " is not shared by a central and a corner green child of one parent");
  // The new diagonal bisects the parent: red, level l-1.
  flip(e, edge_info(true, l - 1));
  ++counters_.swaps_gg;
  return e;
}

EdgeHandle RgbMesh::swap_rb(EdgeHandle e) {
  if (!alive(e)) fail("swap_rb", describe(e) + " does not exist");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  bool ok = is_red(e) && et[1].valid() && level(et[0]) == l && level(et[1]) == l;
  if (ok) {
    const Color c0 = color(et[0]), c1 = color(et[1]);
    ok = (c0 == Color::red && c1 == Color::blue) || (c0 == Color::blue && c1 == Color::red);
  }
  if (!ok) fail("swap_rb", describe(e) + " is not a red edge between a red and a blue triangle");
  // The other diagonal of the trapezoid bisects the same parent: red at the same level.
  flip(e, edge_info(true, l));
  ++counters_.swaps_rb;
  return e;
}

// ---------------------------------------------------------------------------------------
// Selective refinement primitives (section V)

// BB-swaps every unstable pair that the insertion of m created: the blue triangles of a
// split are incident at the new vertex.
void RgbMesh::stabilize_around(VertexHandle m) {
  for (;;) {
    EdgeHandle unstable;
    visit_edges(m, [&](EdgeHandle e) {
      for (TriangleHandle t : e_tri_[e.idx]) {
        if (!t.valid() || color(t) != Color::blue) continue;
        for (EdgeHandle f : t_edge_[t.idx]) {
          if (!is_red(f)) continue;
          const TriangleHandle u = other_triangle(f, t);
          if (u.valid() && color(u) == Color::blue) unstable = f;
          break;
        }
        if (unstable.valid()) return false;
      }
      return true;
    });
    if (!unstable.valid()) return;
    swap_bb(unstable);  // the star changed: look again
  }
}

VertexHandle RgbMesh::split_edge(EdgeHandle e) {
  if (!alive(e)) fail("split_edge", describe(e) + " does not exist");
  if (is_red(e)) fail("split_edge", describe(e) + " is red; only green edges split");
  const int l = level(e);
  if (l >= kMaxLevel) fail("split_edge", describe(e) + " is at the maximum level");
  // Make e refinable: each incident triangle of level l-1 is decomposed by splitting a
  // coarser green edge (section V-B). Splitting other edges never deletes e (green edges are
  // only removed by their own split or by a merge), so the handle stays valid.
  for (;;) {
    EdgeHandle coarser;
    bool swapped = false;
    for (TriangleHandle t : e_tri_[e.idx]) {
      if (!t.valid() || level(t) == l) continue;
      TriangleHandle red = t;
      if (color(t) == Color::blue) {
        // Its red edge leads to the red triangle of the same parent; if that one is blue
        // too (an unstable pair left by hand-applied operators), the BB-swap is the refinement.
        EdgeHandle red_edge;
        for (EdgeHandle f : t_edge_[t.idx]) {
          if (is_red(f)) red_edge = f;
        }
        red = other_triangle(red_edge, t);
        if (color(red) == Color::blue) {
          swap_bb(red_edge);
          swapped = true;
          break;
        }
      }
      for (EdgeHandle f : t_edge_[red.idx]) {
        if (!is_red(f) && level(f) == l - 1) coarser = f;
      }
      break;
    }
    if (swapped) continue;
    if (!coarser.valid()) break;
    split_edge(coarser);
  }
  const SplitKind kind = split_kind(e);
  if (kind == SplitKind::not_refinable) fail("split_edge", "internal error: " + describe(e) + " is still not refinable");
  const VertexHandle m = split_checked_edge(e, kind, "split_edge");
  // Only a red triangle's bisection makes a blue one: GG and green boundary splits cannot
  // leave an unstable pair.
  if (kind != SplitKind::gg && kind != SplitKind::g_boundary) stabilize_around(m);
  return m;
}

void RgbMesh::remove_vertex(VertexHandle v) {
  if (!alive(v)) fail("remove_vertex", describe(v) + " does not exist");
  const auto [a, b] = v_parents_[v.idx];
  // One walk around v checks removability (section IV-D) and finds the halves of its edge.
  const int l = level(v);
  bool removable = l > 0;
  EdgeHandle halves[2];
  visit_edges(v, [&](EdgeHandle e) {
    const VertexHandle w = other_vertex(e, v);
    if (level(w) > l) removable = false;
    if (w == a) halves[0] = e;
    if (w == b) halves[1] = e;
    return removable;
  });
  if (!removable)
    fail("remove_vertex", describe(v) + " is not removable (level 0, or a neighbour has a higher level)");
  // Bring each side of the split edge to a mergeable form by the swaps of Fig. 11. A side is
  // the fan of triangles between the halves (v, a) and (v, b), read counter-clockwise from
  // one of them; as colors it is one of RR, GB, BG (mergeable), GBR, RBG (one RB-swap), GGG
  // (one GG-swap) or GBBG (BB-swap, then GG-swap). Both fans are walked without allocating.
  // (The halves are never swapped, so their handles stay valid throughout.)
  for (int side = 0; side < 2; ++side) {
    for (int step = 0; step < 3; ++step) {
      TriangleHandle fan[5];
      EdgeHandle inner[4];  // inner[i] separates fan[i] and fan[i+1]
      int n = 0;
      EdgeHandle e = halves[side];
      while (n < 5) {
        const auto [t, arriving] = leaving_triangle(v, e);
        if (!t.valid()) break;  // the boundary: this side is read from the other parent
        fan[n++] = t;
        const VertexHandle next = other_vertex(arriving, v);
        if (next == a || next == b) break;
        inner[n - 1] = arriving;
        e = arriving;
      }
      if (n == 0) break;
      char colors[6] = {};
      for (int i = 0; i < n; ++i) colors[i] = color_letter(color(fan[i]));
      const auto is = [&colors](const char* pattern) { return std::strcmp(colors, pattern) == 0; };
      if (is("RR") || is("GB") || is("BG")) break;
      if (is("GBR")) {
        swap_rb(inner[1]);
      } else if (is("RBG")) {
        swap_rb(inner[0]);
      } else if (is("GGG")) {
        swap_gg(inner[1]);
      } else if (is("GBBG")) {
        swap_bb(inner[1]);
      } else {
        fail("remove_vertex", describe(v) + " has an unexpected star side '" + std::string(colors) + "'");
      }
    }
  }
  // Both sides are now in mergeable form (checked in debug builds; validate() checks the result).
  assert(merge_kind(v) != MergeKind::not_mergeable);
  for (const auto& o : removal_observers_) o.cb(v);
  unbisect(v, halves[0], halves[1]);
}

std::string RgbMesh::removal_configuration(VertexHandle v) const {
  if (!alive(v) || !is_removable(v)) return {};
  const auto [a, b] = v_parents_[v.idx];
  VertexStar s;
  star(v, s);
  const std::size_t n = s.edges.size();
  // Read each side counter-clockwise from the parent endpoint where it starts.
  std::string sides[2];
  int count = 0;
  for (std::size_t i = 0; i < n && count < 2; ++i) {
    if (s.neighbors[i] != a && s.neighbors[i] != b) continue;
    std::string colors;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t j = (i + k) % n;
      if (j >= s.triangles.size()) break;
      colors += color_letter(color(s.triangles[j]));
      const VertexHandle next = s.neighbors[(j + 1) % n];
      if (next == a || next == b) break;
    }
    if (!colors.empty()) sides[count++] = colors;
  }
  if (count == 1) return sides[0];
  // A rotation by 180 degrees around v exchanges the sides.
  const std::string x = sides[0] + "|" + sides[1], y = sides[1] + "|" + sides[0];
  return std::min(x, y);
}

// ---------------------------------------------------------------------------------------
// Observers

int RgbMesh::add_insertion_observer(InsertionCallback cb) {
  insertion_observers_.push_back({next_observer_id_, std::move(cb)});
  return next_observer_id_++;
}

int RgbMesh::add_removal_observer(RemovalCallback cb) {
  removal_observers_.push_back({next_observer_id_, std::move(cb)});
  return next_observer_id_++;
}

void RgbMesh::remove_observer(int id) {
  auto drop = [id](auto& list) {
    list.erase(std::remove_if(list.begin(), list.end(), [id](const auto& o) { return o.id == id; }),
               list.end());
  };
  drop(insertion_observers_);
  drop(removal_observers_);
}

// ---------------------------------------------------------------------------------------
// Output

MeshSnapshot RgbMesh::snapshot(Points points, bool geometry_arrays) const {
  MeshSnapshot s;
  std::vector<std::int32_t> index(v_edge_.size(), -1);
  s.points.reserve(n_vertices_);
  NamedArray control{"control_point", 3, {}}, limit{"limit", 3, {}};
  for (VertexHandle v : vertices()) {
    index[v.idx] = static_cast<std::int32_t>(s.points.size());
    const Vec3 c = control_point(v);
    const Vec3 l = (points == Points::limit || geometry_arrays) ? limit_position(v) : Vec3();
    s.points.push_back(points == Points::limit ? l : c);
    s.vertex_level.push_back(v_level_[v.idx]);
    s.vertex_handle.push_back(v);
    if (geometry_arrays) {
      control.values.insert(control.values.end(), {c.x, c.y, c.z});
      limit.values.insert(limit.values.end(), {l.x, l.y, l.z});
    }
  }
  if (geometry_arrays) {
    s.point_data.push_back(std::move(control));
    s.point_data.push_back(std::move(limit));
  }
  s.triangles.reserve(n_triangles_);
  for (TriangleHandle t : triangles()) {
    const auto c = triangle_vertices(t);
    s.triangles.push_back({index[c[0].idx], index[c[1].idx], index[c[2].idx]});
    s.triangle_level.push_back(static_cast<std::uint8_t>(level(t)));
    s.triangle_color.push_back(color(t));
    s.triangle_handle.push_back(t);
  }
  return s;
}

}  // namespace rgbmesh
