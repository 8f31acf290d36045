#pragma once
/// \file
/// RGB triangulations (Puppo & Panozzo, "RGB Subdivision", IEEE TVCG 2009).
///
/// The mesh is the incidence structure of section VII kept as struct-of-arrays with integer
/// handles and free lists: triangle -> 3 edges (counter-clockwise, edge i runs from corner i to
/// corner i+1), edge -> 2 vertices + 2 triangles (the second invalid on the boundary),
/// vertex -> one incident edge. Colors and levels live in one byte per edge and per triangle.
///
/// Combinatorial rules (section IV-A):
///  * a triangle's level is the lowest level of its edges; it is green when its three edges
///    have the same level, red when one edge is one level finer, blue when two are;
///  * a green edge of level l has l = the highest insertion level of its endpoints; a red edge
///    of level l bisects a parent triangle of level l, from the midpoint (level l+1) of one of
///    its edges to the opposite corner;
///  * every vertex of level l > 0 is the midpoint of a green edge of level l-1 whose endpoints
///    (its "parents") it remembers (Fig. 12).
///
/// The eleven local operators of section IV are public, named, and check their preconditions
/// (throwing PreconditionError): four splits, four merges and three swaps, plus the boundary
/// forms of splits and merges. split_edge() and remove_vertex() compose them as in section V.
///
/// Handles and their lifetime
/// --------------------------
/// Elements are named by integer handles (handles.hpp) into slots that free lists reuse.
///  * A vertex handle names its vertex from the insertion until that vertex is removed:
///    remove_vertex(v), merge(v) and the merge_* operators, or removals made for the caller
///    (selective_refinement's coarsening; compute_limits removes only the helper vertices it
///    inserted itself, and restores every edge and triangle slot as it was). Insertions and
///    swaps never invalidate a vertex handle, and a vertex
///    never changes slot. After a removal the slot is reused by a later insertion: an old
///    handle then names another vertex.
///  * Edges and triangles are rewritten in place by the operators around them, so their
///    handles are for use between operations. What holds: while only insertions happen
///    (split_edge, the splits, complete_limit), a green edge keeps its slot and endpoints
///    until it is split itself; the split leaves in its slot the half at its first endpoint
///    (edge_vertices(e)[0]). A swap leaves the new diagonal in the slot of the old one (and
///    returns it). A merge leaves the restored edge in the slot of the half at the first
///    parent (parents(v)[0]). Red edges may be swapped by split_edge's stabilising BB-swaps,
///    and removals swap edges around the removed vertex (Fig. 11). To find an edge again,
///    keep its endpoints and use find_edge(a, b) (selective_refinement's queue does this).
///  * To keep a reference to a vertex across operations, keep its handle and register a
///    removal observer: it is called while the vertex and its data still exist, which is the
///    moment to drop or re-key the reference. Per-vertex data belongs in add_vertex_property,
///    whose values follow the slots (a reused slot starts again from the default value).
///    Identity across a removal and a new insertion: a vertex of level > 0 is the midpoint of
///    the green edge between its parents, so inserting a vertex on that edge again gives the
///    same point of the Loop hierarchy (same level, parents and insertion_point), under a new
///    handle. Keys by parents (recursively down to base vertices, whose handles never change)
///    or by insertion_point survive any sequence of operations.
///  * Using a handle that does not name a live element is a programming error. Operators
///    (splits, merges, swaps, split_edge, remove_vertex, complete_limit) always check and
///    throw PreconditionError. Accessors (level, control_point, edge_vertices, ...) check in
///    builds with checked handles (RGBMESH_CHECKED_HANDLES, the default without NDEBUG): an
///    out-of-range, dead or stale handle (its slot freed since the mesh handed it out, see
///    handles.hpp) prints what was wrong and aborts; in Release builds they do not check at
///    all (no cost), and a stale handle reads whatever the slot holds now. alive(h) says
///    whether h names a live element (in checked builds: the element it was handed out for).
///
/// Exceptions
/// ----------
/// PreconditionError: an operator called on a dead or stale handle or on the wrong
/// configuration; always thrown before anything changes (except those whose message says
/// "internal error": they would be bugs). InputError: from_triangles.
/// std::bad_alloc: arrays that cannot grow. And whatever an observer throws. "Valid" below
/// means validate() is empty; "stable" that validate(true) is.
///  * Queries (const methods) change nothing but the cache of limit positions.
///  * swap_bb, swap_gg, swap_rb: strong guarantee; once the checks pass, nothing can fail.
///  * split_gg ... split_r_boundary, split_refinable: strong for precondition errors. The
///    stencil's limit positions may first need vertices inserted elsewhere (split_edge, below,
///    with its guarantee): an exception there leaves those insertions and no split. The split
///    itself is all or nothing (room is made before anything changes). Observers are told
///    once it is done; if one throws, the split stays and the exception propagates.
///  * merge_r4 ... merge_gb_boundary, merge: strong for precondition errors; then observers
///    are told, then the merge is carried out even if one of them threw (it cannot fail), and
///    the exception propagates afterwards.
///  * split_edge: strong for precondition errors (checked first). It is a sequence of
///    complete steps: the forced splits of coarser neighbours, each a split_edge of its own,
///    then e's split; each step is stabilised (BB-swaps) and then reported to the observers.
///    An exception (an observer's, std::bad_alloc) stops the sequence after a complete step:
///    the mesh is valid, and stable if it was, with e maybe not yet split. complete_limit
///    behaves the same.
///  * remove_vertex: strong for precondition errors; observers are told before anything
///    changes; the swaps and the merge cannot fail and are carried out even if an observer
///    threw; the exception propagates afterwards. The mesh stays valid, and stable if it was.
///  * compute_limits: strong. Any exception undoes every operation it did, exactly (handles
///    included; observers see those removals too), before it propagates; limit positions
///    computed so far stay known.
///  * from_triangles: creates a new mesh or throws (InputError, std::bad_alloc).
///  * Copy assignment, reserve, add_vertex_property, add_*_observer: strong. Moves and
///    remove_observer: no-throw.
///  * Observers are all called for every change that was made, also when one of them throws;
///    the first exception is rethrown once the mesh is consistent as described above, later
///    ones are dropped. They may read the mesh but must not change it or the observer lists.

#include <array>
#include <cassert>
#include <cstdint>
#include <exception>
#include <functional>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/handles.hpp"
#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/sharpness.hpp"
#include "rgbmesh/snapshot.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh {

/// Levels are stored in 6 bits of the triangle byte; 30 is far beyond any practical use
/// (a level-30 uniform refinement of one triangle has 4^30 triangles).
inline constexpr int kMaxLevel = 30;

/// The split variants of Fig. 5, named after the colors of the triangles incident at the edge.
enum class SplitKind : std::uint8_t {
  not_refinable,
  gg,          ///< two green triangles
  rg,          ///< one green, one red
  rr1,         ///< two red, diamond boundary red-green-red-green
  rr2,         ///< two red, diamond boundary red-red-green-green
  g_boundary,  ///< boundary edge of a green triangle
  r_boundary,  ///< boundary edge of a red triangle
};

/// The merge variants (inverses of the splits), named after the star of the vertex.
enum class MergeKind : std::uint8_t {
  not_mergeable,
  r4,           ///< inverts GG-split: four red triangles
  r2gb,         ///< inverts RG-split
  gbgb,         ///< inverts RR1-split
  g2b2,         ///< inverts RR2-split
  r2_boundary,  ///< inverts a boundary split of a green triangle
  gb_boundary,  ///< inverts a boundary split of a red triangle
};

const char* to_string(SplitKind k);
const char* to_string(MergeKind k);

/// Counters of the operations performed since construction (or reset_counters()).
struct OperationCounters {
  std::uint64_t splits = 0;    ///< vertex insertions (all split variants, forced ones included)
  std::uint64_t removals = 0;  ///< vertex removals (all merge variants)
  std::uint64_t swaps_bb = 0;
  std::uint64_t swaps_gg = 0;
  std::uint64_t swaps_rb = 0;
};

/// The star of a vertex in counter-clockwise order. neighbors[i] is the far end of edges[i];
/// triangles[i] lies between edges[i] and edges[i+1] (cyclically for an interior vertex).
/// For a boundary vertex, edges.front() and edges.back() are the boundary edges and there is
/// one triangle fewer than edges.
struct VertexStar {
  std::vector<EdgeHandle> edges;
  std::vector<VertexHandle> neighbors;
  std::vector<TriangleHandle> triangles;
  bool boundary = false;
};

namespace detail {
/// Reports a use of a handle that names no live element, and aborts (checked builds only).
[[noreturn]] void bad_handle(const char* accessor, const std::string& what);
class CreaseTable;  // the sharp features of a base mesh (src/creases.hpp)
struct Ring;
}  // namespace detail

/// Per-vertex user data that follows the mesh's vertex slots (see RgbMesh::add_vertex_property).
class PropertyArrayBase {
 public:
  virtual ~PropertyArrayBase() = default;
  virtual void resize(std::size_t n) = 0;
  /// Gives slot i the default value again (a new vertex in a reused slot).
  virtual void reset(std::size_t i) = 0;
  virtual std::unique_ptr<PropertyArrayBase> clone() const = 0;
  /// Keeps the slots whose new_slot is not -1, each moved down to new_slot (never above its
  /// old slot, in order), in `size` slots: in place (RgbMesh::compact).
  virtual void renumber(const std::vector<std::int32_t>& new_slot, std::size_t size) = 0;
};

template <class T>
class PropertyArray final : public PropertyArrayBase {
 public:
  explicit PropertyArray(T default_value) : default_(std::move(default_value)) {}
  void resize(std::size_t n) override { data.resize(n, default_); }
  void reset(std::size_t i) override { data[i] = default_; }
  std::unique_ptr<PropertyArrayBase> clone() const override {
    return std::make_unique<PropertyArray<T>>(*this);
  }
  void renumber(const std::vector<std::int32_t>& new_slot, std::size_t size) override {
    for (std::size_t i = 0; i < new_slot.size() && i < data.size(); ++i)
      if (new_slot[i] >= 0 && static_cast<std::size_t>(new_slot[i]) != i)
        data[static_cast<std::size_t>(new_slot[i])] = std::move(data[i]);
    if (size < data.size()) data.erase(data.begin() + static_cast<std::ptrdiff_t>(size), data.end());
    data.shrink_to_fit();
  }
  std::vector<T> data;

 private:
  T default_;
};

template <class T>
class VertexProperty {
 public:
  VertexProperty() = default;
  explicit VertexProperty(PropertyArray<T>* a) : array_(a) {}
  T& operator[](VertexHandle v) { return array_->data[slot(v)]; }
  const T& operator[](VertexHandle v) const { return array_->data[slot(v)]; }
  bool valid() const { return array_ != nullptr; }

 private:
  std::size_t slot(VertexHandle v) const {
#if RGBMESH_CHECKED_HANDLES
    if (v.idx < 0 || static_cast<std::size_t>(v.idx) >= array_->data.size())
      detail::bad_handle("VertexProperty::operator[]", "vertex " + std::to_string(v.idx) + " is outside the " +
                                                          std::to_string(array_->data.size()) + " vertex slots");
#endif
    return static_cast<std::size_t>(v.idx);
  }

  PropertyArray<T>* array_ = nullptr;
};

class RgbMesh;

/// Iteration over the live slots of one element kind: `for (VertexHandle v : mesh.vertices())`.
template <class H>
class HandleRange {
 public:
  using AliveFn = bool (*)(const RgbMesh&, std::int32_t);
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = H;
    using difference_type = std::ptrdiff_t;
    using pointer = const H*;
    using reference = H;
    iterator(const HandleRange* r, std::int32_t i) : r_(r), i_(i) { skip(); }
    H operator*() const;  ///< the handle of slot i_, with its generation (defined after RgbMesh)
    iterator& operator++() {
      ++i_;
      skip();
      return *this;
    }
    bool operator!=(const iterator& o) const { return i_ != o.i_; }
    bool operator==(const iterator& o) const { return i_ == o.i_; }

   private:
    void skip() {
      while (i_ < r_->end_ && !r_->alive_(*r_->mesh_, i_)) ++i_;
    }
    const HandleRange* r_;
    std::int32_t i_;
  };
  HandleRange(const RgbMesh& m, std::int32_t end, AliveFn alive) : mesh_(&m), end_(end), alive_(alive) {}
  iterator begin() const { return iterator(this, 0); }
  iterator end() const { return iterator(this, end_); }

 private:
  const RgbMesh* mesh_;
  std::int32_t end_;
  AliveFn alive_;
};

/// What RgbMesh::from_triangles requires of the points besides being finite.
enum class PointRole : std::uint8_t {
  /// Positions of a surface: a triangle of zero area (collinear or coincident corners) is
  /// rejected, as prepare_triangle_mesh rejects it.
  surface,
  /// Any per-vertex values that subdivision carries along (its rules are linear in them), e.g.
  /// the indicator vectors whose limits are the weights of the limit stencils: zero-area
  /// triangles are allowed.
  values,
};

class RgbMesh {
 public:
  RgbMesh() = default;
  RgbMesh(const RgbMesh& other);
  RgbMesh& operator=(const RgbMesh& other);
  RgbMesh(RgbMesh&&) noexcept = default;
  RgbMesh& operator=(RgbMesh&&) noexcept = default;
  ~RgbMesh() = default;

  /// Builds the base mesh Σ0 (all green, level 0): vertex i is points[i], triangle t has the
  /// corners triangles[t] in that (counter-clockwise) order, and their handles are i and t.
  /// It rejects, with prepare_triangle_mesh's checks and messages (one InputError naming the
  /// element), an empty mesh, non-finite coordinates, indices out of range, degenerate
  /// triangles (a repeated vertex, or with PointRole::surface zero area), duplicate triangles
  /// (the same vertex set, such as two triangles glued back to back), edges of more than two
  /// triangles, vertices whose triangles form several fans, and non-orientable surfaces.
  /// Where prepare_triangle_mesh repairs, from_triangles rejects too, since a repair would
  /// change what the caller's indices mean and there is nobody to tell: inconsistently
  /// oriented neighbours ("triangles 3 and 7 are oriented inconsistently across edge (2, 5)")
  /// and unreferenced vertices ("vertex 4 is not referenced by any triangle"), each message
  /// ending "(prepare_triangle_mesh repairs this)". For a mesh from a file, or any other
  /// mesh to be repaired, run prepare_triangle_mesh first.
  static RgbMesh from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles,
                                PointRole role = PointRole::surface);
  /// The same with sharp features (sharpness.hpp): creases and corners that every operation
  /// keeps, so that the mesh is a selectively refined Loop-with-creases mesh (OpenSubdiv's
  /// rules). InputError for an entry that names no edge or vertex of the mesh ("sharp edge 3
  /// (4, 9) is not an edge of the mesh") or has a negative or non-numeric sharpness. Tags on
  /// boundary edges are dropped: boundary edges are infinitely sharp already.
  static RgbMesh from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles,
                                const SharpFeatures& sharp, PointRole role = PointRole::surface);

  // ---- sizes and iteration -------------------------------------------------------------
  std::size_t num_vertices() const { return n_vertices_; }
  std::size_t num_edges() const { return n_edges_; }
  std::size_t num_triangles() const { return n_triangles_; }
  std::int32_t vertex_slots() const { return static_cast<std::int32_t>(v_edge_.size()); }
  std::int32_t edge_slots() const { return static_cast<std::int32_t>(e_vert_.size()); }
  std::int32_t triangle_slots() const { return static_cast<std::int32_t>(t_edge_.size()); }
  std::size_t num_base_vertices() const { return n_base_vertices_; }
  // The base mesh Σ0's triangles exactly as from_triangles was given them (its vertices are
  // the handles 0 .. num_base_vertices()-1, never removed): what a saved state needs to
  // rebuild Σ0 (rgb_state.hpp).
  const std::vector<std::array<std::int32_t, 3>>& base_triangles() const { return base_triangles_; }

  /// Makes room for that many vertices, edges and triangles (slots), so that a large
  /// refinement grows its arrays once instead of by repeated doubling.
  void reserve(std::size_t vertices, std::size_t edges, std::size_t triangles);

  /// The bytes the connectivity and geometry arrays hold now (their capacities; vertex
  /// properties excluded), and what arrays for that many vertices, edges and triangles take:
  /// for memory ceilings and for estimating a refinement before it runs.
  std::size_t memory_bytes() const;
  static std::size_t storage_bytes(std::size_t vertices, std::size_t edges, std::size_t triangles);

  /// Whether h names a live element; with checked handles, also that it is the element h was
  /// handed out for (not a later one in a reused slot).
  bool alive(VertexHandle v) const {
    return in_range(v.idx, v_edge_.size()) && v_edge_[v.idx].valid() && current(v, v_generation_);
  }
  bool alive(EdgeHandle e) const {
    return in_range(e.idx, e_vert_.size()) && e_vert_[e.idx][0].valid() && current(e, e_generation_);
  }
  bool alive(TriangleHandle t) const {
    return in_range(t.idx, t_edge_.size()) && t_edge_[t.idx][0].valid() && current(t, t_generation_);
  }

  HandleRange<VertexHandle> vertices() const;
  HandleRange<EdgeHandle> edges() const;
  HandleRange<TriangleHandle> triangles() const;

  // ---- connectivity ---------------------------------------------------------------------
  /// Every accessor below needs live handles (see "Handles and their lifetime").
  const std::array<VertexHandle, 2>& edge_vertices(EdgeHandle e) const {
    expect_alive(e, "edge_vertices");
    return e_vert_[e.idx];
  }
  const std::array<TriangleHandle, 2>& edge_triangles(EdgeHandle e) const {
    expect_alive(e, "edge_triangles");
    return e_tri_[e.idx];
  }
  const std::array<EdgeHandle, 3>& triangle_edges(TriangleHandle t) const {
    expect_alive(t, "triangle_edges");
    return t_edge_[t.idx];
  }
  std::array<VertexHandle, 3> triangle_vertices(TriangleHandle t) const;  ///< counter-clockwise
  EdgeHandle vertex_edge(VertexHandle v) const {
    expect_alive(v, "vertex_edge");
    return v_edge_[v.idx];
  }

  bool is_boundary(EdgeHandle e) const {
    expect_alive(e, "is_boundary");
    return !e_tri_[e.idx][1].valid();
  }
  bool is_boundary(VertexHandle v) const;
  VertexHandle other_vertex(EdgeHandle e, VertexHandle v) const {
    expect_alive(e, "other_vertex");
    const auto& ev = e_vert_[e.idx];
    return ev[0] == v ? ev[1] : ev[0];
  }
  TriangleHandle other_triangle(EdgeHandle e, TriangleHandle t) const {
    expect_alive(e, "other_triangle");
    const auto& et = e_tri_[e.idx];
    return et[0] == t ? et[1] : et[0];
  }
  VertexHandle opposite_vertex(TriangleHandle t, EdgeHandle e) const;
  EdgeHandle find_edge(VertexHandle a, VertexHandle b) const;  ///< invalid if none
  void star(VertexHandle v, VertexStar& out) const;
  VertexStar star(VertexHandle v) const {
    VertexStar s;
    star(v, s);
    return s;
  }
  int valence(VertexHandle v) const;

  // ---- RGB attributes (section IV-A) ----------------------------------------------------
  int level(VertexHandle v) const {
    expect_alive(v, "level");
    return v_level_[v.idx];
  }
  int level(EdgeHandle e) const {
    expect_alive(e, "level");
    return e_info_[e.idx] & 0x7f;
  }
  int level(TriangleHandle t) const {
    expect_alive(t, "level");
    return t_info_[t.idx] & 0x3f;
  }
  bool is_red(EdgeHandle e) const {
    expect_alive(e, "is_red");
    return (e_info_[e.idx] & 0x80) != 0;
  }
  Color color(EdgeHandle e) const { return is_red(e) ? Color::red : Color::green; }
  Color color(TriangleHandle t) const {
    expect_alive(t, "color");
    return static_cast<Color>(t_info_[t.idx] >> 6);
  }
  /// Endpoints of the edge that v split (Fig. 12); both invalid for base vertices. They are
  /// also the parent triangle's vertices that a red edge ending at v refers to (VI-C).
  const std::array<VertexHandle, 2>& parents(VertexHandle v) const {
    expect_alive(v, "parents");
    return v_parents_[v.idx];
  }
  int max_level() const;

  // ---- geometry: Loop subdivision (section VI) -------------------------------------------
  // Every vertex inserted at level l carries p^l(v), its Loop control point at that level
  // (the base point when l = 0), and, once known, its limit position p_inf(v). Its control
  // point at any finer level follows from those two (Eq. 7, 9). The limit position depends
  // on the base mesh only, so once known it stays valid for as long as v exists.
  //
  // Limit positions are computed lazily and cached; the cache is written by const methods,
  // so a mesh must not be read from several threads at once.

  /// p^l(v) with l = level(v): Loop's odd rule on the stencil of the edge v split.
  const Vec3& insertion_point(VertexHandle v) const {
    expect_alive(v, "insertion_point");
    return v_control_[v.idx];
  }
  /// Whether v lies on the boundary (uses the crease rules of Eq. 2, 5, 8, 9).
  bool is_boundary_vertex(VertexHandle v) const {
    expect_alive(v, "is_boundary_vertex");
    return (v_flags_[v.idx] & kBoundaryFlag) != 0;
  }
  /// The level at which v is shown: the lowest level of its green edges (VI-D).
  int shown_level(VertexHandle v) const;
  /// shown_level of every vertex slot at once (index: the handle's idx; kMaxLevel + 1 for free
  /// slots), in one pass over the edges: what output of the whole mesh needs.
  std::vector<std::uint8_t> shown_levels() const;
  /// p^k(v) for k >= level(v). Needs the limit position when k > level(v).
  Vec3 control_point(VertexHandle v, int k) const;
  /// The control point at the shown level: where v is in the current mesh. In a uniform mesh
  /// of level K this is Loop subdivision's level-K point.
  Vec3 control_point(VertexHandle v) const {
    expect_alive(v, "control_point");
    return control_point(v, shown_level(v));
  }
  /// The point of v in the Loop mesh of level max(l, level(v)) when known without inserting
  /// vertices, else the shown control point. Criteria measure an edge or triangle of level l
  /// with it: unlike shown points, it does not change while the element exists.
  Vec3 level_point(VertexHandle v, int l) const;
  /// Whether limit_position(v) is available: known already, or computable because the Loop
  /// 1-ring of v at its level is in the mesh (recursively for its parents).
  bool has_limit(VertexHandle v) const;
  /// The position of v on the limit surface (Eq. 6, 8); PreconditionError when !has_limit(v).
  Vec3 limit_position(VertexHandle v) const;
  /// Makes the limit position of v available by inserting its missing Loop neighbours (and
  /// those of its parents), as the stencils of section VI-C require (Fig. 13).
  void complete_limit(VertexHandle v);
  /// Makes limit_position() available for every vertex without changing the mesh: missing
  /// neighbours are inserted, the limit positions recorded, and the inserted vertices removed
  /// again (observers see both). Returns how many vertices were inserted and removed. The
  /// mesh is the same afterwards (vertices keep their handles), but triangles and edges that
  /// were removed and re-created may sit in other slots: find them again by their corners.
  std::size_t compute_limits();
  /// The limit positions of the vertices that splitting each edge would insert, without
  /// changing the mesh: the edges are split (with the splits they force), the new vertices'
  /// limits completed and read, and every operation undone in reverse order, as
  /// compute_limits does (observers see both). What quadratic finite elements on the limit
  /// surface place on their edges. An edge that cannot be split (red, or at the maximum level)
  /// gets no value: its entry is NaN. Also makes every vertex's limit position available.
  /// As with compute_limits, triangle and edge handles may name other slots afterwards.
  std::vector<Vec3> split_limits(const std::vector<EdgeHandle>& edges);
  /// The Loop stencil of refinable edge e at its level l: its endpoints, then the vertices
  /// opposite e in the two level-l triangles of the Loop mesh (for a red triangle, the apex
  /// of its parent triangle, VI-C); the last two are invalid on the boundary.
  std::array<VertexHandle, 4> loop_stencil(EdgeHandle e) const;
  /// The control point that splitting refinable edge e gives the new vertex (Eq. 1, 2). Needs the
  /// limit positions of the stencil vertices coarser than e (split_edge provides them).
  Vec3 odd_control_point(EdgeHandle e) const;

  // ---- sharp features (sharpness.hpp) ----------------------------------------------------
  /// Whether the base mesh has any sharp edge or vertex (boundaries aside).
  bool has_sharp_features() const { return creases_ != nullptr; }
  /// The base mesh's sharp features in normal form: interior edges only, each once with
  /// a < b, sorted; vertices sorted; no zero sharpness; values above 10 given as 10.
  const SharpFeatures& sharp_features() const;
  /// The sharpness of edge e at its level: 10 on the boundary, 0 for red edges and edges that
  /// are not pieces of a sharp base edge.
  float sharpness(EdgeHandle e) const;
  /// The sharpness of vertex v at level k >= level(v) (0 for every vertex but the base
  /// vertices tagged sharp).
  float vertex_sharpness(VertexHandle v, int k) const;
  /// The subdivision rule of v at level k >= level(v): from its sharpness and the number of
  /// sharp Loop edges at v on that level (boundary edges count).
  VertexRule vertex_rule(VertexHandle v, int k) const;
  /// vertex_rule at the shown level.
  VertexRule vertex_rule(VertexHandle v) const { return vertex_rule(v, shown_level(v)); }
  /// The rule that splitting green edge e gives its new vertex (loop_rules.hpp): 3/8, 1/8 on
  /// smooth edges, the midpoint on the boundary and on creases, blends on semi-sharp edges.
  loop::OddMask odd_mask(EdgeHandle e) const;

  // ---- predicates -----------------------------------------------------------------------
  /// Green, and every incident triangle has the edge's level (section IV-A).
  bool is_refinable(EdgeHandle e) const;
  /// Level > 0 and no neighbour has a higher level (section IV-D).
  bool is_removable(VertexHandle v) const;
  /// No red edge shared by two blue triangles.
  bool is_stable() const;
  SplitKind split_kind(EdgeHandle e) const;
  /// The green edges whose split raises triangle t's level: its lowest green edges, or for a
  /// blue triangle those of the red triangle across its red edge (section V-B).
  void raising_edges(TriangleHandle t, std::vector<EdgeHandle>& out) const;
  MergeKind merge_kind(VertexHandle v) const;
  /// The star of a removable vertex as one of the 28 configurations of Fig. 11, written as the
  /// colors of the triangles on each side of the split edge read counter-clockwise from a
  /// parent endpoint, e.g. "GBR|RR"; rotations give the same string. Empty if not removable.
  std::string removal_configuration(VertexHandle v) const;

  // ---- the eleven local operators (section IV) -------------------------------------------
  /// Edge splits: insert a vertex at level(e)+1 on a refinable edge; return it.
  VertexHandle split_gg(EdgeHandle e);
  VertexHandle split_rg(EdgeHandle e);
  VertexHandle split_rr1(EdgeHandle e);
  VertexHandle split_rr2(EdgeHandle e);
  VertexHandle split_g_boundary(EdgeHandle e);
  VertexHandle split_r_boundary(EdgeHandle e);
  /// Edge merges: remove a vertex of valence 4 (3 on the boundary); return the restored edge.
  EdgeHandle merge_r4(VertexHandle v);
  EdgeHandle merge_r2gb(VertexHandle v);
  EdgeHandle merge_gbgb(VertexHandle v);
  EdgeHandle merge_g2b2(VertexHandle v);
  EdgeHandle merge_r2_boundary(VertexHandle v);
  EdgeHandle merge_gb_boundary(VertexHandle v);
  /// Edge swaps; return the new edge (the slot of e is reused).
  EdgeHandle swap_bb(EdgeHandle e);  ///< two blue triangles on a red edge -> two green
  EdgeHandle swap_gg(EdgeHandle e);  ///< inverse of swap_bb
  EdgeHandle swap_rb(EdgeHandle e);  ///< red+blue on a red edge -> the other red+blue pair

  /// Applies whichever split variant fits a refinable edge (no stabilising swap).
  VertexHandle split_refinable(EdgeHandle e);
  /// Applies whichever merge variant fits v (no preparatory swaps).
  EdgeHandle merge(VertexHandle v);

  // ---- selective refinement primitives (section V) ----------------------------------------
  /// Splits a green edge, first forcing the splits of coarser neighbours that make it
  /// refinable, and BB-swapping any unstable pair created: the mesh stays stable.
  VertexHandle split_edge(EdgeHandle e);
  /// Removes a removable vertex by the swap sequence of its configuration (Fig. 11) followed
  /// by a merge.
  void remove_vertex(VertexHandle v);

  // ---- uniform levels at once -----------------------------------------------------------
  /// Whether the mesh is one level of Loop subdivision with nothing else in its arrays: every
  /// edge green and of one level (then every triangle is green, of that level) and no free
  /// slot (no removal since the last compaction). What split_all_edges needs.
  bool is_uniform() const;
  /// Splits every edge of a uniform mesh (is_uniform(), else PreconditionError) at once: the
  /// mesh of the next uniform level, the one split_edge on every edge gives (the same
  /// vertices, levels, parents, control points and limit positions; all green, so there is no
  /// diagonal to choose), built in a few passes over the arrays on every core instead of one
  /// operator per edge. The new elements take new slots in the order of what they come from:
  /// the vertex that splits edge e is vertex V + e (V: the vertex slots before), e keeps its
  /// half at edge_vertices(e)[0] and edge E + e is its other half (E: the edge slots before);
  /// triangle t becomes its middle quarter and T + 3t + k its quarter at corner k (T: the
  /// triangle slots before). Insertion observers hear of every new vertex, in that order, once
  /// the level is complete. All or nothing before that: std::bad_alloc leaves the mesh as it was.
  /// Returns the vertices inserted.
  std::size_t split_all_edges();

  // ---- observers --------------------------------------------------------------------------
  /// Called after a vertex is inserted: (new vertex, endpoints of the edge it split). Within
  /// split_edge, once the step that inserted it is complete and stable.
  using InsertionCallback = std::function<void(VertexHandle, VertexHandle, VertexHandle)>;
  /// Called just before a vertex is removed: its handle and data are still valid, and the
  /// mesh is as the caller left it (remove_vertex calls it before its swaps).
  using RemovalCallback = std::function<void(VertexHandle)>;
  /// What happens when an observer throws: see "Exceptions" at the top of this file.
  int add_insertion_observer(InsertionCallback cb);
  int add_removal_observer(RemovalCallback cb);
  void remove_observer(int id);

  // ---- compaction -------------------------------------------------------------------------
  /// Where compact() moved each slot: new_slot[old] for every old slot, -1 for a free one.
  struct Renumbering {
    std::vector<std::int32_t> vertex, edge, triangle;
  };
  using RenumberingCallback = std::function<void(const Renumbering&)>;
  /// Called by compact() once the mesh is renumbered, with the maps (observers that keep data
  /// by slot move it; insertion and removal observers are usually renumbering ones too).
  int add_renumbering_observer(RenumberingCallback cb);
  /// The share of the vertex slots that hold a vertex (1 without free slots). A mesh keeps the
  /// slots of its largest size: after coarsening, most may be free.
  double live_fraction() const;
  /// Gives the free slots' memory back: the live elements move down over the free slots in
  /// their order (an iteration over the mesh visits them in the same order before and after,
  /// base vertices keep slots 0..n-1) and every array is sized to them exactly. The mesh is the
  /// same mesh: triangles, levels, colours, parents, control points, known limit positions,
  /// properties and counters. Handles held outside refer to the old slots: renumbering
  /// observers are told, and the maps are returned; with checked handles, every old handle is
  /// stale. Elements created afterwards take new slots at the end (where they would have
  /// reused free slots): only slot numbers differ from a mesh that was not compacted.
  /// Not from an observer. Strong guarantee (std::bad_alloc leaves the mesh as it was);
  /// a renumbering observer that throws is handled as insertion observers are.
  Renumbering compact();

  // ---- per-vertex properties --------------------------------------------------------------
  /// A value per vertex slot that grows with the mesh; every new vertex starts with
  /// default_value (also in a reused slot). The returned view stays valid for the mesh's
  /// lifetime.
  template <class T>
  VertexProperty<T> add_vertex_property(T default_value = T()) {
    auto arr = std::make_unique<PropertyArray<T>>(std::move(default_value));
    arr->resize(v_edge_.size());
    auto* raw = arr.get();
    vertex_properties_.push_back(std::move(arr));
    return VertexProperty<T>(raw);
  }

  // ---- checks, statistics, output ---------------------------------------------------------
  /// Checks every invariant: array and free-list consistency, incidence symmetry, conformity
  /// (no duplicate edges, each edge in one or two triangles that list it), manifold vertex
  /// stars, consistent orientation, the color/level rules of IV-A, parent references,
  /// Euler characteristic equal to the base mesh's, and stability when asked.
  /// Returns an empty string when all hold, else a description of the first violation.
  std::string validate(bool require_stable = false) const;

  const OperationCounters& counters() const { return counters_; }
  void reset_counters() { counters_ = {}; }
  long euler_characteristic() const {
    return static_cast<long>(n_vertices_) - static_cast<long>(n_edges_) + static_cast<long>(n_triangles_);
  }
  int boundary_loops() const;
  /// A compact copy for output. Points are the shown control points, or the limit positions
  /// (then every vertex needs has_limit(): call compute_limits() first). With geometry_arrays,
  /// the point data also carries both, as "control_point" and "limit".
  enum class Points { control, limit };
  MeshSnapshot snapshot(Points points = Points::control, bool geometry_arrays = false) const;
  /// Fills s.vertex_rule and s.sharp (snapshot.hpp) for the vertices s.vertex_handle lists
  /// (its points), or clears them when the mesh has no sharp features; what snapshot() does.
  void add_sharp_features(MeshSnapshot& s) const;

 private:
  template <class H>
  friend class HandleRange;

  static bool in_range(std::int32_t i, std::size_t n) { return i >= 0 && static_cast<std::size_t>(i) < n; }

  // ---- handle checks (mesh_storage.cpp) ----
  // validate()'s passes (mesh_validate.cpp), each giving the first failure or an empty string:
  // the arrays and free lists (which also finds the live slots), then the edges (which also
  // count each vertex's edges), the triangles, the vertices.
  struct LiveSlots;
  std::string validate_storage(LiveSlots& live) const;
  std::string validate_edges(LiveSlots& live) const;
  std::string validate_triangles(const LiveSlots& live) const;
  std::string validate_vertices(const LiveSlots& live) const;

  /// Each slot counts the elements freed in it (its generation, from 1); handles carry the
  /// count of their slot when the mesh made them. Only with checked handles (handles.hpp).
  /// current: whether h carries its slot's generation; a handle made from a bare index
  /// (generation 0) passes too, unless `stamped_only` (validate: the mesh stores only handles
  /// it stamped itself).
  using Generations = std::vector<std::uint32_t>;
#if RGBMESH_CHECKED_HANDLES
  template <class H>
  static bool current(H h, const Generations& g, bool stamped_only = false) {
    return (h.generation == 0 && !stamped_only) || h.generation == g[static_cast<std::size_t>(h.idx)];
  }
  template <class H>
  static H stamped(H h, const Generations& g) {
    h.generation = g[static_cast<std::size_t>(h.idx)];
    return h;
  }
  template <class H>
  void expect_alive(H h, const char* accessor) const {
    if (!alive(h)) detail::bad_handle(accessor, describe(h) + " is not a live element of this mesh");
  }
#else
  template <class H>
  static bool current(H, const Generations&, bool = false) {
    return true;
  }
  template <class H>
  static H stamped(H h, const Generations&) {
    return h;
  }
  template <class H>
  void expect_alive(H, const char*) const {}
#endif
  /// The handle of a live element's slot, as handed out (with its generation).
  VertexHandle stamped(VertexHandle v) const { return stamped(v, v_generation_); }
  EdgeHandle stamped(EdgeHandle e) const { return stamped(e, e_generation_); }
  TriangleHandle stamped(TriangleHandle t) const { return stamped(t, t_generation_); }

  /// Visits every edge incident at v, in no particular order, without allocating; f returns
  /// false to stop early.
  // Whether edge a comes before edge b in an order of their ends' control points, the same in
  // every copy of the mesh (canonical choices among several candidates).
  bool edge_precedes(EdgeHandle a, EdgeHandle b) const;
  template <class F>
  void visit_edges(VertexHandle v, F&& f) const {
    const EdgeHandle start = v_edge_[v.idx];
    const std::size_t guard = n_edges_ + 1;
    EdgeHandle e = start;
    // Counter-clockwise from the stored edge; if the boundary interrupts, clockwise too.
    for (std::size_t step = 0; step < guard; ++step) {
      if (!f(e)) return;
      e = leaving_triangle(v, e).second;
      if (!e.valid()) break;
      if (e == start) return;
    }
    e = start;
    for (std::size_t step = 0; step < guard; ++step) {
      e = arriving_triangle(v, e).second;
      if (!e.valid() || !f(e)) return;
    }
  }
  std::pair<TriangleHandle, EdgeHandle> leaving_triangle(VertexHandle v, EdgeHandle e) const;
  std::pair<TriangleHandle, EdgeHandle> arriving_triangle(VertexHandle v, EdgeHandle e) const;

  static constexpr std::uint8_t kBoundaryFlag = 1;
  /// On an infinitely sharp base edge: the crease rule with its parents as neighbours, as on
  /// the boundary (its limit and every later control point need only them).
  static constexpr std::uint8_t kCreaseFlag = 2;
  /// On a semi-sharp base edge with a sharp half: its rules change over the levels; its
  /// control points are found from its whole ring (evolve) once that is complete.
  static constexpr std::uint8_t kTransientFlag = 4;
  /// Its control points beyond its level are in history_ (see VertexHistory).
  static constexpr std::uint8_t kHistoryFlag = 8;
  /// A vertex whose rules vary from level to level (semi-sharp features, darts): its control
  /// points p^{l+i} = points[i] (l its level), then p^{l+m+k} = g^k points[m] + (1 - g^k)
  /// p_inf with m = points.size() - 1.
  struct VertexHistory {
    std::vector<Vec3> points;
    double g = 0.25;
  };
  Vec3 history_point(VertexHandle v, int l) const;
  std::size_t history_bytes() const;
  /// The sharp base edge (rail) that a Loop edge is a piece of, and the piece's index along it
  /// at the edge's level; rail -1 if none.
  struct RailPiece {
    std::int32_t rail = -1;
    std::uint64_t piece = 0;
  };
  /// The RailPiece of the Loop edge (a, b) of level l. Inline for the common case, an end
  /// inserted off every rail (a single array read); rail_piece_of otherwise.
  RailPiece rail_piece(VertexHandle a, VertexHandle b, int l) const {
    if (!creases_) return {};
    if ((static_cast<std::size_t>(a.idx) >= n_base_vertices_ && v_rail_[a.idx] < 0) ||
        (static_cast<std::size_t>(b.idx) >= n_base_vertices_ && v_rail_[b.idx] < 0))
      return {};
    return rail_piece_of(a, b, l);
  }
  RailPiece rail_piece_of(VertexHandle a, VertexHandle b, int l) const;
  /// Where x is along rail r at level l (>= level(x)): 0 .. 2^l; -1 if not on it.
  std::int64_t rail_position(VertexHandle x, std::int32_t r, int l) const;
  /// odd_mask for a Loop edge of level l, boundary or not, that is the piece `rp`.
  loop::OddMask odd_mask(const RailPiece& rp, int l, bool boundary) const {
    if (boundary) return {0.5, 0.0};  // Eq. 2
    if (rp.rail < 0) return {};       // Eq. 1
    return sharp_odd_mask(rp, l);
  }
  loop::OddMask sharp_odd_mask(const RailPiece& rp, int l) const;
  /// Gives the new vertex m on the Loop edge of level l that is the piece `rp` its rail and
  /// flags (rp.rail >= 0; a new vertex starts off every rail).
  void place_on_rail(VertexHandle m, const RailPiece& rp, int l);
  /// The Loop 1-ring of v at its level, counter-clockwise, for evolve (false if incomplete).
  template <class Known>
  bool ordered_ring(VertexHandle v, detail::Ring& ring, Known known) const;
  /// The limit and history of a kTransientFlag vertex once its ring is complete.
  bool transient_limit(VertexHandle v) const;
  /// Base vertices with sharp features: their limits, eigenvalues and histories.
  void init_sharp_base_geometry();
  /// Geometry (mesh_geometry.cpp).
  void init_base_geometry();
  VertexHandle stencil_apex(TriangleHandle t, EdgeHandle e) const;
  /// Computes and caches the limit position if the Loop rings allow it; false otherwise.
  bool try_limit(VertexHandle v) const;
  /// try_limit's value for v when the limits of the coarser vertices it needs are stored
  /// (false otherwise, or when v's ring is incomplete); stores nothing, so that several
  /// threads may call it while the mesh does not change.
  bool ring_limit(VertexHandle v, Vec3& limit) const;
  /// The limit position of v from its parents and its Loop ring at its level (VI-A),
  /// once its parents' limits are known; known(w) makes sure (try_limit) or checks
  /// (ring_limit) that a coarser ring vertex w has its limit. False for an incomplete ring.
  template <class Known>
  bool limit_from_ring(VertexHandle v, Vec3& limit, Known known) const;
  /// Stores every limit position the current rings allow for the vertices of levels below
  /// `below_level`, level by level, on several threads for large meshes (compute_limits' first
  /// pass, and split_all_edges' stencils).
  void store_ring_limits(int below_level = kMaxLevel + 1);
  /// Makes the limit positions of the stencil's vertices coarser than l known (may insert
  /// vertices elsewhere); returns whether it had to insert any.
  bool prepare_stencil(const std::array<VertexHandle, 4>& st, int l);
  /// Eq. 1 or 2 on a prepared stencil of level l (a mesh without sharp features), or the rule
  /// `mask` (odd_mask: creases too).
  Vec3 stencil_point(const std::array<VertexHandle, 4>& st, int l) const;
  Vec3 stencil_point(const std::array<VertexHandle, 4>& st, int l, const loop::OddMask& mask) const;
  /// loop_stencil without the precondition check.
  std::array<VertexHandle, 4> stencil(EdgeHandle e) const;
  /// p^l(v) for l >= level(v), with the limit position known when l > level(v).
  Vec3 known_control_point(VertexHandle v, int l) const {
    if (l == level(v)) return v_control_[v.idx];
    if (v_flags_[v.idx] & kHistoryFlag) return history_point(v, l);
    const double g = (static_cast<std::size_t>(v.idx) < base_eigenvalue_.size())
                         ? loop::eigenvalue_power(base_eigenvalue_[v.idx], l - level(v))
                         : std::ldexp(1.0, -2 * (l - level(v)));
    return g * v_control_[v.idx] + (1.0 - g) * limits_[v_limit_index_[v.idx]];
  }
  /// Splits edges until no triangle incident at v is coarser than v.
  void raise_star(VertexHandle v);

  /// While journal_ is set, bisect and flip record themselves so that rollback() can undo
  /// them exactly (handles included), newest first.
  struct JournalEntry {
    enum Kind : std::uint8_t { bisect, flip } kind;
    std::int32_t handle;        ///< the new vertex, or the flipped edge
    std::uint8_t info_before;   ///< the flipped edge's color and level before the flip
  };
  /// Undoes the journal; returns the first exception of a removal observer (all are called).
  std::exception_ptr rollback(const std::vector<JournalEntry>& journal);

  // ---- storage (mesh_storage.cpp) ----
  /// Allocation with slot reuse. Free slots form singly linked lists through the dead slots
  /// themselves (a vertex's first parent, an edge's first triangle, a triangle's second edge
  /// hold the next free slot), newest first: freeing never allocates, so that removals and
  /// the rollback of compute_limits cannot fail halfway. new_* use the room that make_room
  /// made beforehand (mesh_primitives.cpp).
  VertexHandle new_vertex();
  EdgeHandle new_edge(VertexHandle a, VertexHandle b, std::uint8_t info);
  TriangleHandle new_triangle(const std::array<EdgeHandle, 3>& edges);
  void free_vertex(VertexHandle v);
  void free_edge(EdgeHandle e);
  void free_triangle(TriangleHandle t);
  /// Makes room (free slots or capacity) for that many new_vertex / new_edge / new_triangle
  /// calls, so that an operation that calls it first either throws std::bad_alloc before any
  /// change or completes. (new_vertex may still throw from a vertex property's copy; it does
  /// so before changing anything.)
  void make_room(std::size_t vertices, std::size_t edges, std::size_t triangles);
  void grow_vertex_arrays(std::size_t capacity);
  void grow_edge_arrays(std::size_t capacity);
  void grow_triangle_arrays(std::size_t capacity);
  /// The free slots, newest first, read off the lists (for validate()).
  std::vector<std::int32_t> free_vertex_slots() const;
  std::vector<std::int32_t> free_edge_slots() const;
  std::vector<std::int32_t> free_triangle_slots() const;

  /// Topological primitives shared by the named operators (mesh_operators.cpp).
  /// Inserts the vertex with control point `control` (the Loop stencil's value).
  VertexHandle bisect(EdgeHandle e, const Vec3& control, const RailPiece* rail = nullptr);
  void flip(EdgeHandle e, std::uint8_t new_info);
  EdgeHandle unbisect(VertexHandle m);
  EdgeHandle unbisect(VertexHandle m, EdgeHandle half_a, EdgeHandle half_b);  ///< halves at the parents
  /// Room for one more journal entry, so that recording cannot fail after a change.
  void reserve_journal_entry();

  static std::uint8_t edge_info(bool red, int level) {
    return static_cast<std::uint8_t>((red ? 0x80 : 0) | level);
  }
  void update_triangle_info(TriangleHandle t);
  int local_index(TriangleHandle t, EdgeHandle e) const;
  void replace_edge_triangle(EdgeHandle e, TriangleHandle from, TriangleHandle to);

  /// Precondition helpers.
  /// Throws PreconditionError; messages are built only on failure (they are not cheap).
  [[noreturn]] void fail(const char* op, const std::string& what) const;
  std::string describe(EdgeHandle e) const;
  std::string describe(VertexHandle v) const;
  std::string describe(TriangleHandle t) const;
  /// The handle as the mesh hands it out, or PreconditionError "op: <h> does not exist".
  VertexHandle checked(VertexHandle v, const char* op) const;
  EdgeHandle checked(EdgeHandle e, const char* op) const;
  VertexHandle checked_split(EdgeHandle e, SplitKind kind, const char* op);
  /// Prepares the stencil and bisects e (a refinable edge of that kind); no observers yet.
  VertexHandle split_unreported(EdgeHandle e, SplitKind kind, const char* op);
  EdgeHandle checked_merge(VertexHandle v, MergeKind kind, const char* op);
  void stabilize_around(VertexHandle m);

  /// Observers (mesh_storage.cpp). Each calls every observer, even after one threw, and
  /// returns the first exception (empty if none) for the caller to rethrow once the mesh is
  /// consistent.
  [[nodiscard]] std::exception_ptr notify_inserted(VertexHandle v) const;
  [[nodiscard]] std::exception_ptr notify_removing(VertexHandle v) const;
  static void rethrow_if(const std::exception_ptr& e) {
    if (e) std::rethrow_exception(e);
  }

  /// Vertices.
  std::vector<EdgeHandle> v_edge_;  ///< invalid: free slot
  std::vector<std::uint8_t> v_level_;
  std::vector<std::array<VertexHandle, 2>> v_parents_;
  std::vector<Vec3> v_control_;                ///< p^l(v) at insertion level l
  /// Limit positions live in a side table: in a uniform mesh of level K only the vertices
  /// coarser than K need theirs (a quarter), which saves 20 bytes per vertex.
  mutable std::vector<std::int32_t> v_limit_index_;  ///< into limits_, or -1 if not known
  mutable std::vector<Vec3> limits_;
  /// Free entries of limits_, linked through the entries themselves (a free entry's x holds
  /// the next free index, -1 at the end): release_limit then needs no memory of its own and
  /// cannot fail, without a second table as large as limits_.
  mutable std::int32_t limits_free_head_ = -1;
  mutable std::size_t limits_free_count_ = 0;
  /// kBoundaryFlag, kCreaseFlag, kTransientFlag, kHistoryFlag; mutable for kHistoryFlag, which
  /// belongs to the cache of limit positions (set where a limit is first computed).
  mutable std::vector<std::uint8_t> v_flags_;
  bool limit_known(VertexHandle v) const { return v_limit_index_[v.idx] >= 0; }
  void store_limit(VertexHandle v, const Vec3& p) const;
  // Room for `more` limits about to be stored, reserved once at its exact size (not by
  // store_limit's doubling, which would hold up to twice the table when every limit is known).
  void reserve_limits(std::size_t more) const;
  void release_limit(VertexHandle v);
  std::vector<double> base_eigenvalue_;        ///< g of Eq. 7 for each base vertex
  /// Sharp features (null without any): shared by copies, never changed once built.
  std::shared_ptr<const detail::CreaseTable> creases_;
  /// With sharp features only: per vertex slot, the sharp base edge ("rail") an inserted vertex
  /// lies on (-1: none, and for base vertices) and its position there at its level (odd).
  std::vector<std::int32_t> v_rail_;
  std::vector<std::uint32_t> v_rail_position_;
  /// kHistoryFlag vertices, by slot (few: base vertices with sharp features, and vertices on
  /// semi-sharp base edges at the levels where they are sharp).
  mutable std::unordered_map<std::int32_t, VertexHistory> history_;
  std::vector<JournalEntry>* journal_ = nullptr;
  mutable VertexStar scratch_star_;  ///< for merge_kind (the mesh is not for concurrent use)
  std::int32_t v_free_ = -1;           ///< the newest free vertex slot, -1 if none
  Generations v_generation_;           ///< empty without checked handles
  /// Edges.
  std::vector<std::array<VertexHandle, 2>> e_vert_;  ///< [0] invalid: free slot
  std::vector<std::array<TriangleHandle, 2>> e_tri_;
  std::vector<std::uint8_t> e_info_;  ///< bit 7 red, bits 0-6 level
  std::int32_t e_free_ = -1;
  Generations e_generation_;
  /// Triangles.
  std::vector<std::array<EdgeHandle, 3>> t_edge_;  ///< [0] invalid: free slot
  std::vector<std::uint8_t> t_info_;               ///< bits 6-7 color, bits 0-5 level
  std::int32_t t_free_ = -1;
  Generations t_generation_;

  std::size_t n_vertices_ = 0, n_edges_ = 0, n_triangles_ = 0;
  std::size_t n_base_vertices_ = 0;
  std::vector<std::array<std::int32_t, 3>> base_triangles_;  // Σ0, as from_triangles got it
  long base_euler_ = 0;
  OperationCounters counters_;

  std::vector<std::unique_ptr<PropertyArrayBase>> vertex_properties_;
  struct InsertionObserver {
    int id;
    InsertionCallback cb;
  };
  struct RemovalObserver {
    int id;
    RemovalCallback cb;
  };
  struct RenumberingObserver {
    int id;
    RenumberingCallback cb;
  };
  std::vector<InsertionObserver> insertion_observers_;
  std::vector<RemovalObserver> removal_observers_;
  std::vector<RenumberingObserver> renumbering_observers_;
  int next_observer_id_ = 1;
};

template <class H>
H HandleRange<H>::iterator::operator*() const {
  return r_->mesh_->stamped(H(i_));
}

// ---- small navigation steps, inline: every operator runs them many times -------------------

inline std::array<VertexHandle, 3> RgbMesh::triangle_vertices(TriangleHandle t) const {
  expect_alive(t, "triangle_vertices");
  const auto& te = t_edge_[t.idx];
  const auto& a = e_vert_[te[0].idx];
  const auto& b = e_vert_[te[1].idx];
  // Corner 1 is shared by edges 0 and 1; corners 0 and 2 are their other ends.
  const VertexHandle c1 = (a[0] == b[0] || a[0] == b[1]) ? a[0] : a[1];
  const VertexHandle c0 = (c1 == a[0]) ? a[1] : a[0];
  const VertexHandle c2 = (c1 == b[0]) ? b[1] : b[0];
  return {c0, c1, c2};
}

inline int RgbMesh::local_index(TriangleHandle t, EdgeHandle e) const {
  const auto& te = t_edge_[t.idx];
  return te[0] == e ? 0 : (te[1] == e ? 1 : (te[2] == e ? 2 : -1));
}

inline VertexHandle RgbMesh::opposite_vertex(TriangleHandle t, EdgeHandle e) const {
  expect_alive(t, "opposite_vertex");
  const int i = local_index(t, e);
  assert(i >= 0);
  // The far end of the next edge: the endpoint it does not share with e.
  const auto& n = e_vert_[t_edge_[t.idx][(i + 1) % 3].idx];
  const auto& ev = e_vert_[e.idx];
  return (n[0] == ev[0] || n[0] == ev[1]) ? n[1] : n[0];
}

inline void RgbMesh::replace_edge_triangle(EdgeHandle e, TriangleHandle from, TriangleHandle to) {
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

/// The triangle in which e leaves v, and that triangle's edge arriving at v.
inline std::pair<TriangleHandle, EdgeHandle> RgbMesh::leaving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle prev = te[(i + 2) % 3];
    if (e_vert_[prev.idx][0] == v || e_vert_[prev.idx][1] == v) return {t, prev};
  }
  return {TriangleHandle(), EdgeHandle()};
}

/// The triangle in which e arrives at v, and that triangle's edge leaving v.
inline std::pair<TriangleHandle, EdgeHandle> RgbMesh::arriving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle next = te[(i + 1) % 3];
    if (e_vert_[next.idx][0] == v || e_vert_[next.idx][1] == v) return {t, next};
  }
  return {TriangleHandle(), EdgeHandle()};
}

inline VertexHandle RgbMesh::checked(VertexHandle v, const char* op) const {
  if (!alive(v)) fail(op, describe(v) + " does not exist");
  return stamped(v);
}

inline EdgeHandle RgbMesh::checked(EdgeHandle e, const char* op) const {
  if (!alive(e)) fail(op, describe(e) + " does not exist");
  return stamped(e);
}

}  // namespace rgbmesh
