// Saving and restoring the RGB state (rgb_state.hpp). Restoring trusts nothing in the state:
// every index is range-checked before use, the mesh itself recomputes levels, colours and
// geometry, and whatever the file also says about them is compared with the result.

#include "rgbmesh/rgb_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"

namespace rgbmesh {
namespace {

std::string str(std::int64_t i) { return std::to_string(i); }

[[noreturn]] void inconsistent(const std::string& what) { throw InputError("inconsistent RGB state: " + what); }

// The inserted points by their parents' pair, without hashing: the children of point p whose
// smaller parent is p are listed together (a counting sort by that parent), each with its
// other parent. A point has a few such children, so a look-up reads one short run.
class ChildIndex {
 public:
  // The point whose parents are a and b (in either order), or -1. Ids from n on (the helper
  // vertices of Replay) have no children here.
  std::int32_t find(std::int32_t a, std::int32_t b) const {
    if (a > b) std::swap(a, b);
    if (a < 0 || static_cast<std::size_t>(a) + 1 >= first_.size()) return -1;
    for (std::int32_t i = first_[a]; i < first_[a + 1]; ++i)
      if (other_[i] == b) return child_[i];
    return -1;
  }

  // From parents already checked: every inserted point has two different parents in range.
  void build(const RgbState& s) {
    const std::size_t n = s.parents.size();
    first_.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (s.base_vertex[i] < 0) ++first_[std::min(s.parents[i][0], s.parents[i][1]) + 1];
    for (std::size_t p = 0; p < n; ++p) first_[p + 1] += first_[p];
    other_.resize(static_cast<std::size_t>(first_[n]));
    child_.resize(static_cast<std::size_t>(first_[n]));
    std::vector<std::int32_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (s.base_vertex[i] >= 0) continue;
      const auto [p0, p1] = s.parents[i];
      const std::int32_t slot = next[std::min(p0, p1)]++;
      other_[slot] = std::max(p0, p1);
      child_[slot] = static_cast<std::int32_t>(i);  // increasing within each run
    }
  }

  // The first point (in index order) that splits the same pair as an earlier one: {earlier,
  // later}, or {-1, -1}.
  std::array<std::int32_t, 2> first_duplicate() const {
    std::array<std::int32_t, 2> found{-1, -1};
    for (std::size_t p = 0; p + 1 < first_.size(); ++p)
      for (std::int32_t i = first_[p]; i < first_[p + 1]; ++i)
        for (std::int32_t j = i + 1; j < first_[p + 1]; ++j)
          if (other_[i] == other_[j] && (found[1] < 0 || child_[j] < found[1])) found = {child_[i], child_[j]};
    return found;
  }

 private:
  std::vector<std::int32_t> first_;  // per point p, where its run starts; then the end
  std::vector<std::int32_t> other_;  // the other (larger) parent
  std::vector<std::int32_t> child_;
};

// Checks the arrays by themselves: sizes, ranges, each base vertex once, parents that are
// other points; and indexes the inserted vertices by their parents' pair.
ChildIndex check_arrays(const RgbState& s) {
  if (s.version < 1 || s.version > RgbState::kVersion)
    inconsistent("version " + str(s.version) + " is not supported (this build reads versions 1 to " +
                 str(RgbState::kVersion) + ")");
  if (s.version < 2 && !s.sharp.empty()) inconsistent("version 1 has no sharp features");
  const std::size_t n = s.parents.size();
  if (s.base_vertex.size() != n)
    inconsistent(str(static_cast<std::int64_t>(s.base_vertex.size())) + " base indices for " +
                 str(static_cast<std::int64_t>(n)) + " points");
  if (n > static_cast<std::size_t>(INT32_MAX)) inconsistent("too many points");
  const auto n0 = static_cast<std::int64_t>(s.base_points.size());
  std::vector<std::int32_t> point_of_base(s.base_points.size(), -1);
  for (std::size_t i = 0; i < n; ++i) {
    const auto point = static_cast<std::int32_t>(i);
    const std::int32_t b = s.base_vertex[i];
    const auto [p0, p1] = s.parents[i];
    if (b >= 0) {
      if (b >= n0)
        inconsistent("point " + str(point) + " is base vertex " + str(b) + ", but the base mesh has " + str(n0));
      if (p0 != -1 || p1 != -1) inconsistent("point " + str(point) + " is a base vertex but has parents");
      if (point_of_base[b] >= 0)
        inconsistent("points " + str(point_of_base[b]) + " and " + str(point) + " are both base vertex " + str(b));
      point_of_base[b] = point;
      continue;
    }
    if (b != -1) inconsistent("point " + str(point) + " has base index " + str(b));
    for (const std::int32_t p : {p0, p1})
      if (p < 0 || static_cast<std::size_t>(p) >= n || p == point)
        inconsistent("point " + str(point) + " has parent " + str(p) + " (points are 0 to " +
                     str(static_cast<std::int64_t>(n) - 1) + ")");
    if (p0 == p1) inconsistent("point " + str(point) + " has the same parent twice");
  }
  ChildIndex children;
  children.build(s);
  if (const auto [earlier, later] = children.first_duplicate(); later >= 0)
    inconsistent("points " + str(earlier) + " and " + str(later) + " both split the edge between points " +
                 str(s.parents[later][0]) + " and " + str(s.parents[later][1]));
  for (std::size_t b = 0; b < point_of_base.size(); ++b)
    if (point_of_base[b] < 0)
      inconsistent("base vertex " + str(static_cast<std::int64_t>(b)) + " is missing (base vertices are never removed)");
  return children;
}

// Inserts the state's vertices into the base mesh, each after its parents, and records which
// vertex every point became.
class Replay {
 public:
  Replay(const RgbState& s, RgbMesh& mesh, ChildIndex children)
      : s_(s), mesh_(mesh), children_(std::move(children)), vertex_(s.parents.size()), mark_(s.parents.size(), 0) {
    point_of_slot_.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
    for (std::size_t i = 0; i < s.parents.size(); ++i) {
      if (s.base_vertex[i] < 0) continue;
      vertex_[i] = VertexHandle(s.base_vertex[i]);
      point_of_slot_[static_cast<std::size_t>(s.base_vertex[i])] = static_cast<std::int32_t>(i);
      mark_[i] = kDone;
    }
  }

  std::vector<VertexHandle> run() {
    // Every vertex split_edge creates (forced or asked for) is matched to its point here.
    const int id = mesh_.add_insertion_observer([this](VertexHandle v, VertexHandle a, VertexHandle b) { created(v, a, b); });
    try {
      for (std::size_t i = 0; i < vertex_.size(); ++i) insert_with_ancestors(static_cast<std::int32_t>(i));
      remove_extras();
    } catch (...) {
      mesh_.remove_observer(id);
      throw;
    }
    mesh_.remove_observer(id);
    return std::move(vertex_);
  }

 private:
  static constexpr std::uint8_t kOnPath = 1, kDone = 2;

  // Depth first along the parents, one missing parent at a time, so that the stack is a chain
  // of descendants: a parent already on it closes a cycle.
  void insert_with_ancestors(std::int32_t point) {
    if (mark_[point] == kDone) return;
    path_.assign(1, point);
    mark_[point] = kOnPath;
    while (!path_.empty()) {
      const std::int32_t k = path_.back();
      if (mark_[k] == kDone) {
        path_.pop_back();
        continue;
      }
      std::int32_t missing = -1;
      for (const std::int32_t p : s_.parents[k])
        if (mark_[p] != kDone) missing = p;
      if (missing >= 0) {
        if (mark_[missing] == kOnPath) inconsistent("point " + str(k) + " is among its own ancestors");
        mark_[missing] = kOnPath;
        path_.push_back(missing);
        continue;
      }
      insert(k);
      path_.pop_back();
    }
  }

  // Splits the edge between the parents of `point`; split_edge forces what it needs first.
  void insert(std::int32_t point) {
    const auto [p0, p1] = s_.parents[point];
    const EdgeHandle e = mesh_.find_edge(vertex_[p0], vertex_[p1]);
    if (!e.valid())
      inconsistent("point " + str(point) + " splits the edge between points " + str(p0) + " and " + str(p1) +
                   ", which are not joined by an edge");
    if (mesh_.is_red(e))
      inconsistent("point " + str(point) + " splits the edge between points " + str(p0) + " and " + str(p1) +
                   ", which is a red edge");
    if (mesh_.level(e) + 1 > kMaxLevel)
      inconsistent("point " + str(point) + " would have level " + str(mesh_.level(e) + 1) + ", above " + str(kMaxLevel));
    current_ = point;
    try {
      mesh_.split_edge(e);
    } catch (const PreconditionError& error) {
      inconsistent("point " + str(point) + " cannot be inserted: " + error.what());
    }
    if (mark_[point] != kDone)  // cannot happen: the split of e makes the vertex of (p0, p1)
      throw std::logic_error("restore_state: point " + str(point) + " was not created by its own split");
  }

  void created(VertexHandle v, VertexHandle a, VertexHandle b) {
    const std::int32_t pa = point_of(a), pb = point_of(b);
    const std::int32_t k = children_.find(pa, pb);
    if (k < 0) {
      // Not saved: a helper that the split's Loop stencil needed for a limit position (the
      // original process may have needed others), or a forced vertex the state lacks. Which
      // one is known at the end, when finish() tries to remove it.
      const auto id = static_cast<std::int32_t>(vertex_.size() + extras_.size());
      extras_.push_back({v, current_, pa, pb});
      remember(v, id);
      return;
    }
    if (mark_[k] == kDone)  // cannot happen: an existing midpoint's edge no longer exists
      throw std::logic_error("restore_state: point " + str(k) + " was created twice");
    vertex_[k] = v;
    mark_[k] = kDone;
    remember(v, k);
  }

  void remember(VertexHandle v, std::int32_t id) {
    if (static_cast<std::size_t>(v.idx) >= point_of_slot_.size())
      point_of_slot_.resize(std::max<std::size_t>(2 * point_of_slot_.size(), static_cast<std::size_t>(v.idx) + 1), -1);
    point_of_slot_[static_cast<std::size_t>(v.idx)] = id;
  }

  // Removes the vertices that are not saved, finest first; one that cannot be removed is
  // needed by saved vertices, which the state should then have listed.
  void remove_extras() {
    std::stable_sort(extras_.begin(), extras_.end(),
                     [this](const Extra& a, const Extra& b) { return mesh_.level(a.v) > mesh_.level(b.v); });
    for (bool progress = true; progress;) {
      progress = false;
      for (Extra& x : extras_) {
        if (!x.v.valid() || !mesh_.is_removable(x.v)) continue;
        mesh_.remove_vertex(x.v);
        x.v = VertexHandle();
        progress = true;
      }
    }
    for (const Extra& x : extras_)
      if (x.v.valid())
        inconsistent("inserting point " + str(x.inserting) + " forces a vertex between " + name(x.a) + " and " +
                     name(x.b) + ", which the state does not have");
  }

  std::string name(std::int32_t id) const {
    const auto n = static_cast<std::int32_t>(vertex_.size());
    return id < n ? "point " + str(id) : "the midpoint of " + name(extras_[id - n].a) + " and " + name(extras_[id - n].b);
  }

  std::int32_t point_of(VertexHandle v) const {
    // Every vertex of the mesh is a base vertex or was created under this observer.
    return point_of_slot_.at(static_cast<std::size_t>(v.idx));
  }

  const RgbState& s_;
  RgbMesh& mesh_;
  ChildIndex children_;
  std::vector<VertexHandle> vertex_;
  std::vector<std::uint8_t> mark_;
  std::vector<std::int32_t> point_of_slot_;
  std::vector<std::int32_t> path_;
  std::int32_t current_ = -1;
  struct Extra {
    VertexHandle v;       // invalid once removed
    std::int32_t inserting;  // the point whose insertion created it
    std::int32_t a, b;    // its parents' ids (points, or n + index of an extra)
  };
  std::vector<Extra> extras_;
};

std::string triangle_text(const std::array<std::int32_t, 3>& t) {
  return "(points " + str(t[0]) + ", " + str(t[1]) + ", " + str(t[2]) + ")";
}

bool in_range(const std::array<std::int32_t, 3>& t, std::size_t n) {
  for (const std::int32_t v : t)
    if (v < 0 || static_cast<std::size_t>(v) >= n) return false;
  return true;
}

// A triangle's corners rotated so that the smallest comes first: two triangles have the same
// corners in the same cyclic order exactly when these are equal.
std::array<std::int32_t, 3> smallest_first(const std::array<std::int32_t, 3>& t) {
  const int k = t[0] <= t[1] ? (t[0] <= t[2] ? 0 : 2) : (t[1] <= t[2] ? 1 : 2);
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

// The mesh's triangles in the state's point indices, grouped by their smallest corner (a
// counting sort), so that a triangle of the file is found by reading one short run: walking
// around a vertex for each of millions of triangles cost more than the refinement itself.
class TriangleIndex {
 public:
  explicit TriangleIndex(const RestoredMesh& r) {
    const std::size_t n = r.vertex.size();
    std::vector<std::int32_t> point_of_slot(static_cast<std::size_t>(r.mesh.vertex_slots()), -1);
    for (std::size_t i = 0; i < n; ++i) point_of_slot[static_cast<std::size_t>(r.vertex[i].idx)] = static_cast<std::int32_t>(i);
    std::vector<std::array<std::int32_t, 3>> corners;
    std::vector<TriangleHandle> handles;
    corners.reserve(r.mesh.num_triangles());
    handles.reserve(r.mesh.num_triangles());
    for (const TriangleHandle t : r.mesh.triangles()) {
      const auto v = r.mesh.triangle_vertices(t);
      const std::array<std::int32_t, 3> c{point_of_slot[static_cast<std::size_t>(v[0].idx)],
                                          point_of_slot[static_cast<std::size_t>(v[1].idx)],
                                          point_of_slot[static_cast<std::size_t>(v[2].idx)]};
      if (c[0] < 0 || c[1] < 0 || c[2] < 0) continue;  // not a point (cannot happen): never found
      corners.push_back(smallest_first(c));
      handles.push_back(t);
    }
    first_.assign(n + 1, 0);
    for (const auto& c : corners) ++first_[static_cast<std::size_t>(c[0]) + 1];
    for (std::size_t p = 0; p < n; ++p) first_[p + 1] += first_[p];
    entries_.resize(corners.size());
    std::vector<std::int32_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t j = 0; j < corners.size(); ++j)
      entries_[static_cast<std::size_t>(next[static_cast<std::size_t>(corners[j][0])]++)] = {corners[j][1], corners[j][2],
                                                                                          handles[j]};
  }

  // The mesh's triangle with these corners (points in range) in this cyclic order, or an
  // invalid handle.
  TriangleHandle find(const std::array<std::int32_t, 3>& t) const {
    const auto c = smallest_first(t);
    for (std::int32_t i = first_[c[0]]; i < first_[c[0] + 1]; ++i)
      if (entries_[i].b == c[1] && entries_[i].c == c[2]) return entries_[i].t;
    return TriangleHandle();
  }

 private:
  struct Entry {
    std::int32_t b, c;  // the corners after the smallest, in order
    TriangleHandle t;
  };
  std::vector<std::int32_t> first_;  // per point, where the run of its triangles starts
  std::vector<Entry> entries_;
};

// The vertex set leaves one choice open (tests/test_rgb_state.cpp found it): a parent triangle
// with two split edges is a green corner and a trapezoid, and which diagonal of the trapezoid
// is the red edge depends on the order of the insertions. Where the file has the diagonal
// (p, q) and the mesh the other one, that red edge is swapped (swap_rb). Anything else that
// differs is left for check_triangles to report.
void choose_diagonal(RgbMesh& mesh, VertexHandle p, VertexHandle q) {
  const VertexStar star = mesh.star(p);
  for (const TriangleHandle t : star.triangles) {
    for (const EdgeHandle e : mesh.triangle_edges(t)) {
      const auto& ends = mesh.edge_vertices(e);
      if (ends[0] == p || ends[1] == p || !mesh.is_red(e) || mesh.is_boundary(e)) continue;
      if (mesh.opposite_vertex(mesh.other_triangle(e, t), e) != q) continue;
      try {
        mesh.swap_rb(e);
      } catch (const PreconditionError&) {
      }
      return;
    }
  }
}

void choose_diagonals(RestoredMesh& r, const std::vector<std::array<std::int32_t, 3>>& triangles,
                      const std::vector<std::size_t>& missing) {
  for (const std::size_t j : missing) {
    const auto& t = triangles[j];
    for (int k = 0; k < 3; ++k) {
      const VertexHandle p = r.vertex[t[k]], q = r.vertex[t[(k + 1) % 3]];
      if (p != q && !r.mesh.find_edge(p, q).valid()) choose_diagonal(r.mesh, p, q);
    }
  }
}

// The expected triangles must be exactly the mesh's, each once; then their levels and colours.
// With `missing`, triangles the mesh does not have are listed there instead of refused.
void check_triangles(const RestoredMesh& r, const RestoreExpectations& x, std::vector<std::size_t>* missing) {
  std::vector<char> seen(static_cast<std::size_t>(r.mesh.triangle_slots()), 0);
  const TriangleIndex index(r);
  for (std::size_t j = 0; j < x.triangles.size(); ++j) {
    const auto name = [&] { return "triangle " + str(static_cast<std::int64_t>(j)); };
    if (!in_range(x.triangles[j], r.vertex.size()))
      inconsistent(name() + " " + triangle_text(x.triangles[j]) + " names a point that does not exist");
    const TriangleHandle t = index.find(x.triangles[j]);
    if (!t.valid() && missing != nullptr) {
      missing->push_back(j);
      continue;
    }
    if (!t.valid())
      inconsistent(name() + " " + triangle_text(x.triangles[j]) + " is not a triangle of the mesh the state describes");
    if (seen[static_cast<std::size_t>(t.idx)]) inconsistent(name() + " is listed twice");
    seen[static_cast<std::size_t>(t.idx)] = 1;
    if (j < x.triangle_level.size() && x.triangle_level[j] != r.mesh.level(t))
      inconsistent(name() + " has level " + str(x.triangle_level[j]) + ", but the state gives level " +
                   str(r.mesh.level(t)));
    if (j < x.triangle_color.size() && x.triangle_color[j] != static_cast<std::uint8_t>(r.mesh.color(t)))
      inconsistent(name() + " has colour " + str(x.triangle_color[j]) + ", but the state gives colour " +
                   str(static_cast<int>(r.mesh.color(t))));
  }
  if ((missing == nullptr || missing->empty()) && x.triangles.size() != r.mesh.num_triangles())
    inconsistent("the state describes " + str(static_cast<std::int64_t>(r.mesh.num_triangles())) +
                 " triangles, the file has " + str(static_cast<std::int64_t>(x.triangles.size())));
}

// shown_level of every vertex slot, in one pass over the edges (as RgbMesh::snapshot does)
// rather than a walk around each vertex.
std::vector<std::uint8_t> shown_levels(const RgbMesh& mesh) {
  std::vector<std::uint8_t> shown(static_cast<std::size_t>(mesh.vertex_slots()), static_cast<std::uint8_t>(kMaxLevel + 1));
  for (const EdgeHandle e : mesh.edges()) {
    if (mesh.is_red(e)) continue;
    const auto l = static_cast<std::uint8_t>(mesh.level(e));
    for (const VertexHandle v : mesh.edge_vertices(e)) shown[v.idx] = std::min(shown[v.idx], l);
  }
  return shown;
}

// Compares per-point positions with the mesh's, within 1e-9 of their bounding-box diagonal.
template <class Position>
void check_positions(const RestoredMesh& r, const std::vector<Vec3>& expected, const char* what, Position of) {
  if (expected.empty()) return;
  if (expected.size() != r.vertex.size())
    inconsistent(str(static_cast<std::int64_t>(expected.size())) + " " + what + "s for " +
                 str(static_cast<std::int64_t>(r.vertex.size())) + " points");
  Vec3 lo = expected[0], hi = expected[0];
  for (const Vec3& p : expected) {
    lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  const double tolerance = 1e-9 * std::max(norm(hi - lo), 1e-300);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double d = norm(of(r.vertex[i]) - expected[i]);
    if (!(d <= tolerance))
      inconsistent("point " + str(static_cast<std::int64_t>(i)) + ": the file's " + what + " is " +
                   std::to_string(d) + " away from the one the state gives (edited base points?)");
  }
}

}  // namespace

namespace {

// The state of `entries` (each a live vertex, once; `entry_of_slot` their indices by slot,
// which must hold every parent of an inserted entry): the base mesh, and per entry its base
// index or its parents' entries.
RgbState state_of(const RgbMesh& mesh, const std::vector<VertexHandle>& entries,
                  const std::vector<std::int32_t>& entry_of_slot) {
  RgbState s;
  s.base_points.reserve(mesh.num_base_vertices());
  for (std::size_t b = 0; b < mesh.num_base_vertices(); ++b)
    s.base_points.push_back(mesh.insertion_point(VertexHandle(static_cast<std::int32_t>(b))));
  s.base_triangles = mesh.base_triangles();
  s.sharp = mesh.sharp_features();
  s.version = RgbState::version_for(s.sharp);
  s.base_vertex.resize(entries.size());
  s.parents.resize(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const VertexHandle v = entries[i];
    if (mesh.level(v) == 0) {  // base vertices keep the handles from_triangles gave them
      s.base_vertex[i] = v.idx;
      s.parents[i] = {-1, -1};
    } else {
      const auto& p = mesh.parents(v);
      s.base_vertex[i] = -1;
      s.parents[i] = {entry_of_slot[static_cast<std::size_t>(p[0].idx)],
                      entry_of_slot[static_cast<std::size_t>(p[1].idx)]};
    }
  }
  return s;
}

}  // namespace

RgbState save_state(const RgbMesh& mesh, const MeshSnapshot& snapshot) {
  const std::size_t n = snapshot.vertex_handle.size();
  if (n != mesh.num_vertices())
    throw std::invalid_argument("save_state: the snapshot has " + std::to_string(n) + " points, the mesh " +
                                std::to_string(mesh.num_vertices()) + " vertices");
  if (mesh.base_triangles().empty())
    throw std::invalid_argument("save_state: the mesh was not made by RgbMesh::from_triangles");
  std::vector<std::int32_t> point_of_slot(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  for (std::size_t i = 0; i < n; ++i) {
    const VertexHandle v = snapshot.vertex_handle[i];
    if (!mesh.alive(v) || point_of_slot[static_cast<std::size_t>(v.idx)] >= 0)
      throw std::invalid_argument("save_state: snapshot point " + std::to_string(i) +
                                  " is not a vertex of the mesh, or a vertex listed twice");
    point_of_slot[static_cast<std::size_t>(v.idx)] = static_cast<std::int32_t>(i);
  }
  return state_of(mesh, snapshot.vertex_handle, point_of_slot);
}

RestoredMesh restore_state(const RgbState& state, const RestoreExpectations& expected) {
  ChildIndex children = check_arrays(state);
  RestoredMesh r;
  try {
    r.mesh = RgbMesh::from_triangles(state.base_points, state.base_triangles, state.sharp);
  } catch (const InputError& e) {
    inconsistent(std::string("the base mesh: ") + e.what());
  }
  const std::size_t n = state.parents.size();
  r.mesh.reserve(n, 3 * n, 2 * n);
  r.vertex = Replay(state, r.mesh, std::move(children)).run();
  if (!expected.vertex_level.empty()) {
    if (expected.vertex_level.size() != n)
      inconsistent(str(static_cast<std::int64_t>(expected.vertex_level.size())) + " levels for " +
                   str(static_cast<std::int64_t>(n)) + " points");
    for (std::size_t i = 0; i < n; ++i)
      if (expected.vertex_level[i] != r.mesh.level(r.vertex[i]))
        inconsistent("point " + str(static_cast<std::int64_t>(i)) + " has level " + str(expected.vertex_level[i]) +
                     ", but its parents give level " + str(r.mesh.level(r.vertex[i])));
  }
  if (!expected.triangles.empty()) {
    std::vector<std::size_t> missing;
    check_triangles(r, expected, &missing);
    if (!missing.empty()) {
      choose_diagonals(r, expected.triangles, missing);
      check_triangles(r, expected, nullptr);
    }
  }
  // The operators keep the mesh valid whatever the state says; this is the last line of
  // defence against a bug of ours turning an odd file into a corrupt mesh.
  if (const std::string problem = r.mesh.validate(true); !problem.empty())
    inconsistent("the rebuilt mesh is not valid: " + problem);
  if (!expected.control_points.empty() || !expected.limits.empty()) {
    r.mesh.compute_limits();  // leaves the mesh as it is
    if (!expected.control_points.empty()) {
      const std::vector<std::uint8_t> shown = shown_levels(r.mesh);
      check_positions(r, expected.control_points, "control point",
                      [&](VertexHandle v) { return r.mesh.control_point(v, shown[v.idx]); });
    }
    check_positions(r, expected.limits, "limit position", [&](VertexHandle v) { return r.mesh.limit_position(v); });
  }
  return r;
}

RgbState save_piece_state(const RgbMesh& mesh, const std::vector<VertexHandle>& points) {
  if (mesh.base_triangles().empty())
    throw std::invalid_argument("save_piece_state: the mesh was not made by RgbMesh::from_triangles");
  std::vector<std::int32_t> entry_of_slot(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  std::vector<VertexHandle> entries;
  entries.reserve(points.size());
  const auto add = [&](VertexHandle v) {
    entry_of_slot[static_cast<std::size_t>(v.idx)] = static_cast<std::int32_t>(entries.size());
    entries.push_back(v);
  };
  for (const VertexHandle v : points) {
    if (!mesh.alive(v) || entry_of_slot[static_cast<std::size_t>(v.idx)] >= 0)
      throw std::invalid_argument(
          "save_piece_state: a point is not a vertex of the mesh, or a vertex listed twice");
    add(v);
  }
  // The ancestors not among the points: parents of entries, until closed.
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (mesh.level(entries[i]) == 0) continue;
    for (const VertexHandle p : mesh.parents(entries[i]))
      if (entry_of_slot[static_cast<std::size_t>(p.idx)] < 0) add(p);
  }
  return state_of(mesh, entries, entry_of_slot);
}

RgbState join_piece_states(const std::vector<RgbState>& pieces,
                           std::vector<std::vector<std::int32_t>>& entry_of) {
  RgbState whole;
  entry_of.assign(pieces.size(), {});
  if (pieces.empty()) inconsistent("no pieces");
  whole.base_points = pieces[0].base_points;
  whole.base_triangles = pieces[0].base_triangles;
  whole.sharp = pieces[0].sharp;
  whole.version = RgbState::version_for(whole.sharp);
  std::unordered_map<VertexName, std::int32_t> at;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const RgbState& s = pieces[k];
    const std::string piece = "piece " + str(static_cast<std::int64_t>(k)) + ": ";
    if (s.version < 1 || s.version > RgbState::kVersion)
      inconsistent(piece + "version " + str(s.version) + " is not supported (this build reads versions 1 to " +
                   str(RgbState::kVersion) + ")");
    if (s.base_triangles != whole.base_triangles || s.sharp != whole.sharp || s.base_points.size() != whole.base_points.size() ||
        !std::equal(s.base_points.begin(), s.base_points.end(), whole.base_points.begin(),
                    [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }))
      inconsistent(piece + "its base mesh differs from piece 0's (pieces of different runs?)");
    const std::size_t n = s.parents.size();
    if (s.base_vertex.size() != n)
      inconsistent(piece + str(static_cast<std::int64_t>(s.base_vertex.size())) + " base indices for " +
                   str(static_cast<std::int64_t>(n)) + " entries");
    if (n > static_cast<std::size_t>(INT32_MAX)) inconsistent(piece + "too many entries");
    // Names by ancestry, parents first: an explicit stack (a hostile file's chains may be
    // long), a cycle refused. 0: not named yet, 1: on the stack, 2: named.
    std::vector<VertexName> name(n, 0);
    std::vector<char> state(n, 0);
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < n; ++start) {
      if (state[start] == 2) continue;
      stack.push_back(start);
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        if (state[i] == 2) {  // (pushed twice: a common ancestor)
          stack.pop_back();
          continue;
        }
        const auto entry = str(static_cast<std::int64_t>(i));
        const std::int32_t b = s.base_vertex[i];
        if (b >= 0) {
          if (static_cast<std::size_t>(b) >= whole.base_points.size() || s.parents[i][0] != -1 ||
              s.parents[i][1] != -1)
            inconsistent(piece + "entry " + entry + " is base vertex " + str(b) + " of " +
                         str(static_cast<std::int64_t>(whole.base_points.size())) + ", or has parents too");
          name[i] = static_cast<VertexName>(b);
          state[i] = 2;
          stack.pop_back();
          continue;
        }
        const auto [p0, p1] = s.parents[i];
        if (b != -1 || p0 < 0 || p1 < 0 || static_cast<std::size_t>(p0) >= n ||
            static_cast<std::size_t>(p1) >= n || p0 == p1)
          inconsistent(piece + "entry " + entry + " has base index " + str(b) + " and parents " + str(p0) +
                       ", " + str(p1));
        state[i] = 1;
        bool ready = true;
        for (const std::int32_t p : {p0, p1}) {
          if (state[static_cast<std::size_t>(p)] == 2) continue;
          if (state[static_cast<std::size_t>(p)] == 1)
            inconsistent(piece + "entry " + entry + " is its own ancestor");
          stack.push_back(static_cast<std::size_t>(p));
          ready = false;
        }
        if (!ready) continue;
        name[i] = child_name(name[static_cast<std::size_t>(p0)], name[static_cast<std::size_t>(p1)]);
        state[i] = 2;
        stack.pop_back();
      }
    }
    // Joined by names; parents as the joined entries (every parent is an entry of the piece).
    std::vector<std::int32_t>& mine = entry_of[k];
    mine.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      const auto [it, fresh] = at.try_emplace(name[i], static_cast<std::int32_t>(whole.parents.size()));
      mine[i] = it->second;
      if (!fresh) continue;
      whole.base_vertex.push_back(s.base_vertex[i]);
      whole.parents.push_back({-1, -1});
    }
    for (std::size_t i = 0; i < n; ++i)
      if (s.base_vertex[i] < 0)
        whole.parents[static_cast<std::size_t>(mine[i])] = {mine[static_cast<std::size_t>(s.parents[i][0])],
                                                            mine[static_cast<std::size_t>(s.parents[i][1])]};
  }
  return whole;
}

}  // namespace rgbmesh
