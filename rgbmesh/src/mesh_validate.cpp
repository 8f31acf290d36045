// RgbMesh::validate(): every structural and RGB invariant, checked from scratch.

#include <cmath>
#include <algorithm>
#include <sstream>

#include "creases.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

namespace {

// Collects the first failure; later checks are skipped once one failed.
class Checker {
 public:
  template <class... Args>
  bool fail(const Args&... args) {
    if (message_.empty()) {
      std::ostringstream s;
      (s << ... << args);
      message_ = s.str();
    }
    return false;
  }
  bool ok() const { return message_.empty(); }
  std::string message() const { return message_; }

 private:
  std::string message_;
};

template <class Free>
bool check_free_list(Checker& c, const char* kind, const Free& free_list, std::int32_t slots,
                     std::size_t alive_count, const std::vector<bool>& alive) {
  std::vector<bool> in_free(static_cast<std::size_t>(slots), false);
  for (std::int32_t i : free_list) {
    if (i < 0 || i >= slots) return c.fail(kind, " free list holds out-of-range slot ", i);
    if (in_free[i]) return c.fail(kind, " free list holds slot ", i, " twice");
    if (alive[i]) return c.fail(kind, " free list holds live slot ", i);
    in_free[i] = true;
  }
  std::size_t n_alive = 0;
  for (std::int32_t i = 0; i < slots; ++i) {
    if (alive[i])
      ++n_alive;
    else if (!in_free[i])
      return c.fail(kind, " slot ", i, " is dead but not in the free list");
  }
  if (n_alive != alive_count)
    return c.fail(kind, " count is ", alive_count, " but ", n_alive, " slots are alive");
  return true;
}

}  // namespace

// The live slots of each kind, and (from the edge pass) each vertex's number of edges. A
// stored handle must name a live element and (checked handles) carry its slot's current
// generation: the mesh never keeps a handle it could not hand out.
struct RgbMesh::LiveSlots {
  explicit LiveSlots(const RgbMesh& m)
      : mesh(m), nv(m.vertex_slots()), ne(m.edge_slots()), nt(m.triangle_slots()) {}
  const RgbMesh& mesh;
  std::int32_t nv, ne, nt;
  std::vector<bool> v_alive, e_alive, t_alive;
  std::vector<int> degree;

  bool v_ok(VertexHandle v) const {
    return v.idx >= 0 && v.idx < nv && v_alive[v.idx] && current(v, mesh.v_generation_, true);
  }
  bool e_ok(EdgeHandle e) const {
    return e.idx >= 0 && e.idx < ne && e_alive[e.idx] && current(e, mesh.e_generation_, true);
  }
  bool t_ok(TriangleHandle t) const {
    return t.idx >= 0 && t.idx < nt && t_alive[t.idx] && current(t, mesh.t_generation_, true);
  }
};

std::string RgbMesh::validate(bool require_stable) const {
  LiveSlots live(*this);
  std::string failure = validate_storage(live);
  if (failure.empty()) failure = validate_edges(live);
  if (failure.empty()) failure = validate_triangles(live);
  if (failure.empty()) failure = validate_vertices(live);
  if (!failure.empty()) return failure;
  if (euler_characteristic() != base_euler_)
    return "Euler characteristic changed from " + std::to_string(base_euler_) + " to " +
           std::to_string(euler_characteristic());
  if (require_stable && !is_stable()) {
    for (EdgeHandle e : edges()) {
      const auto& et = e_tri_[e.idx];
      if (is_red(e) && et[1].valid() && color(et[0]) == Color::blue && color(et[1]) == Color::blue)
        return "unstable: " + describe(e) + " is shared by two blue triangles";
    }
  }
  return {};
}

std::string RgbMesh::validate_storage(LiveSlots& live) const {
  Checker c;
  const std::int32_t nv = live.nv, ne = live.ne, nt = live.nt;
  if (v_level_.size() != v_edge_.size() || v_parents_.size() != v_edge_.size() ||
      v_control_.size() != v_edge_.size() || v_limit_index_.size() != v_edge_.size() ||
      v_flags_.size() != v_edge_.size())
    return "vertex arrays have different sizes";
  if (creases_ ? (v_rail_.size() != v_edge_.size() || v_rail_position_.size() != v_edge_.size())
               : (!v_rail_.empty() || !v_rail_position_.empty() || !history_.empty()))
    return "the sharp-feature arrays do not match the vertex slots";
  if (e_tri_.size() != e_vert_.size() || e_info_.size() != e_vert_.size())
    return "edge arrays have different sizes";
  if (t_info_.size() != t_edge_.size()) return "triangle arrays have different sizes";
#if RGBMESH_CHECKED_HANDLES
  if (v_generation_.size() != v_edge_.size() || e_generation_.size() != e_vert_.size() ||
      t_generation_.size() != t_edge_.size())
    return "generation arrays do not match the slots";
#endif
  {
    // The free entries of the limit table: a list without cycles, of the length counted.
    std::size_t free = 0;
    for (double next = limits_free_head_; next != -1.0; next = limits_[static_cast<std::size_t>(next)].x) {
      if (!(next >= 0.0 && next < static_cast<double>(limits_.size())) || next != std::floor(next) ||
          ++free > limits_.size())
        return "the free list of limit positions leaves the table or loops";
    }
    if (free != limits_free_count_) return "the free list of limit positions has a wrong length";
  }

  std::vector<bool>& v_alive = live.v_alive;
  std::vector<bool>& e_alive = live.e_alive;
  std::vector<bool>& t_alive = live.t_alive;
  v_alive.resize(static_cast<std::size_t>(nv));
  e_alive.resize(static_cast<std::size_t>(ne));
  t_alive.resize(static_cast<std::size_t>(nt));
  for (std::int32_t i = 0; i < nv; ++i) v_alive[i] = v_edge_[i].valid();
  for (std::int32_t i = 0; i < ne; ++i) e_alive[i] = e_vert_[i][0].valid();
  for (std::int32_t i = 0; i < nt; ++i) t_alive[i] = t_edge_[i][0].valid();
  if (!check_free_list(c, "vertex", free_vertex_slots(), nv, n_vertices_, v_alive) ||
      !check_free_list(c, "edge", free_edge_slots(), ne, n_edges_, e_alive) ||
      !check_free_list(c, "triangle", free_triangle_slots(), nt, n_triangles_, t_alive))
    return c.message();
  return {};
}

std::string RgbMesh::validate_edges(LiveSlots& live) const {
  Checker c;
  // Edges: live endpoints, distinct; one or two triangles that list the edge (conformity: an
  // edge in a triangle is the whole side, no T-junction). That no two edges join one vertex
  // pair is checked with the vertices' stars below (a hash set of the pairs took about 40% of
  // validate() on a million vertices).
  live.degree.assign(static_cast<std::size_t>(live.nv), 0);
  for (std::int32_t i = 0; i < live.ne && c.ok(); ++i) {
    if (!live.e_alive[i]) continue;
    const EdgeHandle e(i);
    const auto& ev = e_vert_[i];
    if (!live.v_ok(ev[0]) || !live.v_ok(ev[1])) {
      c.fail(describe(e), " has a dead endpoint (or a stale handle of one)");
      break;
    }
    if (ev[0] == ev[1]) {
      c.fail(describe(e), " is a loop");
      break;
    }
    ++live.degree[ev[0].idx];
    ++live.degree[ev[1].idx];
    const auto& et = e_tri_[i];
    if (!live.t_ok(et[0])) {
      c.fail(describe(e), " has no first triangle (or a stale handle of it)");
      break;
    }
    if (et[1].valid() && !live.t_ok(et[1])) {
      c.fail(describe(e), " has a dead second triangle (or a stale handle of it)");
      break;
    }
    if (et[0] == et[1]) {
      c.fail(describe(e), " lists one triangle twice");
      break;
    }
    for (TriangleHandle t : et) {
      if (t.valid() && local_index(t, e) < 0)
        c.fail(describe(e), " lists triangle ", t.idx, " which does not contain it");
    }
    if (!c.ok()) break;
    // Orientation (an interior edge traversed in opposite directions by its triangles) is
    // checked in the triangle loop, which has the corners at hand.
    // Color and level of edges (section IV-A): a green edge of level l has l = the highest
    // level of its endpoints; a red edge of level l joins a midpoint of level l+1 to a
    // parent corner.
    const int lv = std::max(v_level_[ev[0].idx], v_level_[ev[1].idx]);
    const int le = level(e);
    if (!is_red(e) && le != lv) c.fail(describe(e), " is green but its highest endpoint level is ", lv);
    if (is_red(e)) {
      if (le != lv - 1) c.fail(describe(e), " is red but its highest endpoint level is ", lv);
      if (!et[1].valid()) c.fail(describe(e), " is red and on the boundary");
      for (TriangleHandle t : et) {
        if (t.valid() && (level(t) != le || color(t) == Color::green))
          c.fail(describe(e), " is red but triangle ", t.idx, " is not a red or blue one of its level");
      }
    }
  }
  return c.message();
}

std::string RgbMesh::validate_triangles(const LiveSlots& live) const {
  Checker c;
  // Triangles: three distinct live edges chaining into a cycle; the cached color and level
  // match the edges; the edge colors fit the triangle color. Each edge lies in exactly the
  // triangles it lists (both loops check it), so recording the direction in which each of them
  // traverses it (bit 1: from edge_vertices[0] to [1], bit 2: back) finds two triangles that
  // traverse an edge the same way: inconsistent orientation.
  std::vector<std::uint8_t> traversed(static_cast<std::size_t>(live.ne), 0);
  for (std::int32_t i = 0; i < live.nt && c.ok(); ++i) {
    if (!live.t_alive[i]) continue;
    const TriangleHandle t(i);
    const auto& te = t_edge_[i];
    for (EdgeHandle e : te) {
      if (!live.e_ok(e)) {
        c.fail("triangle ", i, " has a dead edge ", e.idx, " (or a stale handle of it)");
        break;
      }
      if (e_tri_[e.idx][0] != t && e_tri_[e.idx][1] != t) {
        c.fail("triangle ", i, " holds ", describe(e), " which does not list it");
        break;
      }
    }
    if (!c.ok()) break;
    if (te[0] == te[1] || te[1] == te[2] || te[2] == te[0]) {
      c.fail("triangle ", i, " repeats an edge");
      break;
    }
    // Consecutive edges share exactly the corner between them.
    for (int k = 0; k < 3; ++k) {
      const auto& a = e_vert_[te[k].idx];
      const auto& b = e_vert_[te[(k + 1) % 3].idx];
      const int shared = (a[0] == b[0]) + (a[0] == b[1]) + (a[1] == b[0]) + (a[1] == b[1]);
      if (shared != 1)
        c.fail("triangle ", i, ": edges ", te[k].idx, " and ", te[(k + 1) % 3].idx, " do not chain");
    }
    if (!c.ok()) break;
    const auto cv = triangle_vertices(t);
    for (int k = 0; k < 3; ++k) {
      const auto& ev = e_vert_[te[k].idx];
      const bool fits =
          (ev[0] == cv[k] && ev[1] == cv[(k + 1) % 3]) || (ev[1] == cv[k] && ev[0] == cv[(k + 1) % 3]);
      if (!fits) {
        c.fail("triangle ", i, ": edge ", te[k].idx, " is not between corners ", k, " and ", (k + 1) % 3);
        break;
      }
      const std::uint8_t direction = ev[0] == cv[k] ? 1 : 2;
      std::uint8_t& seen = traversed[static_cast<std::size_t>(te[k].idx)];
      if (seen & direction) {
        const auto& et = e_tri_[te[k].idx];
        c.fail(describe(te[k]), ": triangles ", et[0].idx, " and ", et[1].idx, " are inconsistently oriented");
        break;
      }
      seen |= direction;
    }
    if (cv[0] == cv[1] || cv[1] == cv[2] || cv[2] == cv[0]) c.fail("triangle ", i, " is degenerate");
    if (!c.ok()) break;
    const int lo = std::min({level(te[0]), level(te[1]), level(te[2])});
    int finer = 0, red_edges = 0, red_at_lo = 0;
    for (EdgeHandle e : te) {
      const int d = level(e) - lo;
      if (d > 1) c.fail("triangle ", i, ": edge levels differ by more than one");
      finer += d;
      if (is_red(e)) {
        ++red_edges;
        if (d == 0) ++red_at_lo;
      }
    }
    if (level(t) != lo || static_cast<int>(color(t)) != finer)
      c.fail("triangle ", i, ": cached color/level disagree with its edges");
    // Green: three green edges. Red: {green l, red l, green l+1}. Blue: {red l, green l+1 x2}.
    const bool edges_fit = (finer == 0 && red_edges == 0) ||
                           (finer == 1 && red_edges == 1 && red_at_lo == 1) ||
                           (finer == 2 && red_edges == 1 && red_at_lo == 1);
    if (!edges_fit)
      c.fail("triangle ", i, " (", "GRB"[finer], ", level ", lo, ") has edges of the wrong colors");
  }
  return c.message();
}

std::string RgbMesh::validate_vertices(const LiveSlots& live) const {
  Checker c;
  // Vertices: the stored edge is incident; the star is one fan covering every incident edge
  // (manifold) with a different neighbour at each (so no two edges join the same pair: both
  // would be incident at either end); levels and parents follow the split rule.
  VertexStar s;
  std::vector<VertexHandle> sorted_neighbors;
  for (std::int32_t i = 0; i < live.nv && c.ok(); ++i) {
    if (!live.v_alive[i]) continue;
    const VertexHandle v(i);
    const EdgeHandle e = v_edge_[i];
    if (!live.e_ok(e)) {
      c.fail(describe(v), " stores a dead edge (or a stale handle of it)");
      break;
    }
    if (e_vert_[e.idx][0] != v && e_vert_[e.idx][1] != v) {
      c.fail(describe(v), " stores a non-incident edge");
      break;
    }
    star(v, s);
    if (static_cast<int>(s.edges.size()) != live.degree[i]) {
      c.fail(describe(v), " is non-manifold: its fan has ", s.edges.size(), " of ", live.degree[i], " edges");
      break;
    }
    {
      const std::vector<VertexHandle>& w = s.neighbors;
      VertexHandle repeated;
      if (w.size() <= 16) {  // the usual valences: pairwise, without sorting
        for (std::size_t a = 0; a < w.size() && !repeated.valid(); ++a)
          for (std::size_t b = a + 1; b < w.size(); ++b)
            if (w[a] == w[b]) repeated = w[a];
      } else {
        sorted_neighbors.assign(w.begin(), w.end());
        std::sort(sorted_neighbors.begin(), sorted_neighbors.end(),
                  [](VertexHandle x, VertexHandle y) { return x.idx < y.idx; });
        const auto it = std::adjacent_find(sorted_neighbors.begin(), sorted_neighbors.end());
        if (it != sorted_neighbors.end()) repeated = *it;
      }
      if (repeated.valid()) {
        c.fail("two edges join vertices ", std::min(i, repeated.idx), " and ", std::max(i, repeated.idx));
        break;
      }
    }
    const auto& p = v_parents_[i];
    if (v_level_[i] == 0) {
      if (p[0].valid() || p[1].valid()) c.fail(describe(v), " is a base vertex with parents");
    } else {
      if (!live.v_ok(p[0]) || !live.v_ok(p[1])) {
        c.fail(describe(v), " has a dead parent (or a stale handle of it)");
      } else if (std::max(v_level_[p[0].idx], v_level_[p[1].idx]) != v_level_[i] - 1) {
        c.fail(describe(v), ": its parents are not a green edge of level ", v_level_[i] - 1);
      }
    }
    if (static_cast<std::size_t>(i) < n_base_vertices_ && v_level_[i] != 0)
      c.fail(describe(v), " occupies a base slot but is not a base vertex");
    // Geometry (section VI): a finite control point, the boundary flag that selects the
    // crease rules, and a limit position wherever the vertex is shown above its own level
    // (all its level-l edges split, so its Loop ring is complete; VI-D).
    if (!is_finite(v_control_[i])) c.fail(describe(v), " has a non-finite control point");
    if (is_boundary_vertex(v) != s.boundary) c.fail(describe(v), " has a wrong boundary flag");
    if (c.ok() && creases_) {
      // Sharp features: the base edge and position an inserted vertex lies on follow from its
      // parents, and so do its flags; a stored history is found.
      const std::int32_t rail = v_rail_[i];
      const std::uint8_t flags = v_flags_[i];
      if (v_level_[i] > 0) {
        const int l = v_level_[i] - 1;
        const RailPiece rp = rail_piece_of(p[0], p[1], l);
        const std::int32_t expected = rp.rail;
        const std::uint64_t piece = rp.piece;
        if (rail != expected || (rail >= 0 && v_rail_position_[i] != 2 * piece + 1))
          c.fail(describe(v), " has a wrong sharp base edge (", rail, " instead of ", expected, ")");
        const float h0 = rail < 0 ? 0.0f : creases_->segment(rail, l + 1, 2 * piece);
        const float h1 = rail < 0 ? 0.0f : creases_->segment(rail, l + 1, 2 * piece + 1);
        const bool crease = loop::is_infinitely_sharp(h0) && loop::is_infinitely_sharp(h1);
        const bool transient = !crease && (loop::is_semi_sharp(h0) || loop::is_semi_sharp(h1));
        if (crease != ((flags & kCreaseFlag) != 0) || transient != ((flags & kTransientFlag) != 0))
          c.fail(describe(v), " has wrong crease flags");
      } else if (rail != -1) {
        c.fail(describe(v), " is a base vertex with a sharp base edge");
      }
      if (((flags & kHistoryFlag) != 0) != (history_.count(i) == 1))
        c.fail(describe(v), " has a history flag that does not match the stored histories");
    }
    // shown_level(v), from the star just walked (it holds every incident edge).
    int shown = kMaxLevel + 1;
    for (const EdgeHandle e_at_v : s.edges)
      if (!is_red(e_at_v)) shown = std::min(shown, level(e_at_v));
    if (c.ok() && shown > v_level_[i] && !has_limit(v))
      c.fail(describe(v), " is shown at level ", shown, " but its limit position is unknown");
  }
  return c.message();
}

}  // namespace rgbmesh
