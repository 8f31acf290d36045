#include "rgbmesh/parallel/partition.hpp"

#include <metis.h>

#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/refinement.hpp"

namespace rgbmesh::parallel {

namespace {

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The smallest cell of the macro mesh holding a point: a macro vertex, the inside of a macro
// edge (its ends), or the inside of a macro triangle.
struct Cell {
  enum Kind : std::uint8_t { none, on_vertex, on_edge, in_face } kind = none;
  std::int32_t a = -1, b = -1;  // vertex: a; edge: a < b (vertex slots)
  std::int32_t face = -1;
};

class MacroCells {
 public:
  explicit MacroCells(const MacroTriangles& m) : m_(m) {
    faces_of_edge_.reserve(m.corners.size() * 2);
    for (std::size_t f = 0; f < m.corners.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        auto& faces = faces_of_edge_.try_emplace(key(f, k), std::array<std::int32_t, 2>{-1, -1}).first->second;
        faces[faces[0] < 0 ? 0 : 1] = static_cast<std::int32_t>(f);
      }
    }
  }
  std::uint64_t key(std::size_t f, int k) const {
    return edge_key(m_.corners[f][k].idx, m_.corners[f][(k + 1) % 3].idx);
  }
  const std::array<std::int32_t, 2>* faces(std::int32_t a, std::int32_t b) const {
    const auto it = faces_of_edge_.find(edge_key(a, b));
    return it == faces_of_edge_.end() ? nullptr : &it->second;
  }
  bool has_corner(std::int32_t f, std::int32_t v) const {
    for (const VertexHandle c : m_.corners[static_cast<std::size_t>(f)])
      if (c.idx == v) return true;
    return false;
  }
  // The smallest cell holding two cells' points and every point between them.
  Cell join(const Cell& x, const Cell& y) const {
    if (x.kind == Cell::in_face || y.kind == Cell::in_face) {
      const Cell& f = x.kind == Cell::in_face ? x : y;
      const Cell& o = x.kind == Cell::in_face ? y : x;
      const bool inside = o.kind == Cell::in_face    ? o.face == f.face
                          : o.kind == Cell::on_edge  ? has_corner(f.face, o.a) && has_corner(f.face, o.b)
                                                  : has_corner(f.face, o.a);
      if (!inside) fail();
      return f;
    }
    if (x.kind == Cell::on_vertex && y.kind == Cell::on_vertex) {
      if (x.a == y.a) return x;
      if (!faces(x.a, y.a)) fail();
      return {Cell::on_edge, std::min(x.a, y.a), std::max(x.a, y.a), -1};
    }
    if (x.kind == Cell::on_edge && y.kind == Cell::on_edge) {
      if (x.a == y.a && x.b == y.b) return x;
      return {Cell::in_face, -1, -1, face_with(x, [&](std::int32_t f) { return has_corner(f, y.a) && has_corner(f, y.b); })};
    }
    const Cell& e = x.kind == Cell::on_edge ? x : y;
    const Cell& v = x.kind == Cell::on_edge ? y : x;
    if (v.a == e.a || v.a == e.b) return e;
    return {Cell::in_face, -1, -1, face_with(e, [&](std::int32_t f) { return has_corner(f, v.a); })};
  }

 private:
  template <class Holds>
  std::int32_t face_with(const Cell& e, Holds holds) const {
    const auto* f = faces(e.a, e.b);
    if (!f) fail();
    for (const std::int32_t face : *f)
      if (face >= 0 && holds(face)) return face;
    fail();
  }
  [[noreturn]] static void fail() {
    throw std::logic_error("macro_triangles: a vertex is not between its parents' macro cells");
  }
  const MacroTriangles& m_;
  std::unordered_map<std::uint64_t, std::array<std::int32_t, 2>> faces_of_edge_;
};

}  // namespace

namespace {

// The uniform mesh of one level, small beside the mesh, with each of its vertices named by the
// mesh's vertex slot (the same vertex: the same parents), or by a negative number of its own
// where the mesh does not have that vertex (it is coarser there).
struct UniformMesh {
  int level = 0;
  RgbMesh mesh;
  std::vector<std::int32_t> slot;  // per vertex slot of `mesh`
};

// At the floor: a copy of the mesh coarsened to it (every triangle is at the floor or finer, so
// the copy only loses vertices, and those it keeps keep their handles).
UniformMesh uniform_at_floor(const RgbMesh& mesh, int level) {
  UniformMesh u{level, mesh, {}};
  selective_refinement(u.mesh, UniformLevel(level));
  u.slot.resize(static_cast<std::size_t>(u.mesh.vertex_slots()), -1);
  for (const VertexHandle v : u.mesh.vertices()) u.slot[static_cast<std::size_t>(v.idx)] = v.idx;
  return u;
}

// One level down: the uniform mesh refined once (cheap: it is small), its new vertices found in
// the mesh by their parents (`child`: the mesh's vertices by their parents' slots).
UniformMesh uniform_below(const UniformMesh& above, const std::unordered_map<std::uint64_t, std::int32_t>& child,
                          std::int32_t& next_missing) {
  UniformMesh u{above.level + 1, above.mesh, {}};
  selective_refinement(u.mesh, UniformLevel(u.level));
  u.slot.assign(static_cast<std::size_t>(u.mesh.vertex_slots()), -1);
  std::vector<VertexHandle> fresh;
  for (const VertexHandle v : u.mesh.vertices()) {
    // (Insertions keep the handles of the vertices that were there: the new ones are the
    // level's own.)
    if (u.mesh.level(v) < u.level) {
      u.slot[static_cast<std::size_t>(v.idx)] = above.slot[static_cast<std::size_t>(v.idx)];
    } else {
      fresh.push_back(v);
    }
  }
  for (const VertexHandle v : fresh) {
    const auto& p = u.mesh.parents(v);
    const std::int32_t a = u.slot[static_cast<std::size_t>(p[0].idx)], b = u.slot[static_cast<std::size_t>(p[1].idx)];
    const auto it = a >= 0 && b >= 0 ? child.find(edge_key(a, b)) : child.end();
    u.slot[static_cast<std::size_t>(v.idx)] = it != child.end() ? it->second : next_missing--;
  }
  return u;
}

// The uniform mesh's triangles as macro triangles (corners named by the mesh's slots, and
// their neighbours), with the lookup of their edges: what placing a mesh's triangles needs
// besides the mesh itself, kept with the floor's uniform mesh (FloorCache) because a
// distributed run places its view's triangles several times a cycle.
struct MacroSkeleton {
  MacroTriangles m;  // (without of_triangle and triangles)
  std::unique_ptr<MacroCells> cells;
  // Per triangle slot of the meshes placed with names: the corners' names and the macro
  // triangle of the triangle placed there last. Names do not depend on slots, so a slot
  // holding corners of the same names holds the same triangle, and most of a view's triangles
  // are unchanged from one placement to the next.
  struct Placed {
    std::array<VertexName, 3> corner{};
    std::int32_t face = -1;
  };
  mutable std::vector<Placed> placed;
};

std::unique_ptr<MacroSkeleton> skeleton_of(const UniformMesh& uniform) {
  auto out = std::make_unique<MacroSkeleton>();
  MacroTriangles& m = out->m;
  m.level = uniform.level;
  m.corners.reserve(uniform.mesh.num_triangles());
  // The cells in an order that depends on the uniform mesh alone (its triangles by their
  // corners' names), not on the slots a copy of the mesh gave them: processes holding other
  // pieces of one mesh number the cells alike (shared_units).
  const std::vector<VertexName> name = vertex_names(uniform.mesh);
  std::vector<std::pair<std::array<VertexName, 3>, TriangleHandle>> sorted;
  sorted.reserve(uniform.mesh.num_triangles());
  for (const TriangleHandle t : uniform.mesh.triangles()) {
    const auto c = uniform.mesh.triangle_vertices(t);
    std::array<VertexName, 3> key{name[c[0].idx], name[c[1].idx], name[c[2].idx]};
    std::sort(key.begin(), key.end());
    sorted.emplace_back(key, t);
  }
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [key, t] : sorted) {
    std::array<VertexHandle, 3> c = uniform.mesh.triangle_vertices(t);
    for (VertexHandle& v : c) v = VertexHandle(uniform.slot[static_cast<std::size_t>(v.idx)]);
    m.corners.push_back(c);
  }
  out->cells = std::make_unique<MacroCells>(m);
  const MacroCells& cells = *out->cells;
  m.across.assign(m.corners.size(), {-1, -1, -1});
  for (std::size_t f = 0; f < m.corners.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const auto* faces = cells.faces(m.corners[f][k].idx, m.corners[f][(k + 1) % 3].idx);
      const std::int32_t other = (*faces)[0] == static_cast<std::int32_t>(f) ? (*faces)[1] : (*faces)[0];
      m.across[f][k] = other;
    }
  }
  return out;
}

// The macro triangles of a skeleton, with the mesh's triangles placed in them; a triangle
// coarser than the level gets -1 (its corners' cells are macro vertices that no macro edge
// joins). `number`: per vertex slot of the mesh, the skeleton's number of each vertex at or
// below its level (empty: the slot itself, for a skeleton made from this mesh's slots).
// `name`: the mesh's vertex names, for a skeleton kept between calls (FloorCache): a triangle
// whose corners have the names they had at the last call is where it was then, and only the
// others, and their corners, are placed anew.
MacroTriangles place_in(const RgbMesh& mesh, const MacroSkeleton& skeleton, const std::vector<std::int32_t>& number = {},
                        const std::vector<VertexName>* name = nullptr) {
  using Placed = MacroSkeleton::Placed;
  const auto number_of = [&number](VertexHandle v) {
    return number.empty() ? v.idx : number[static_cast<std::size_t>(v.idx)];
  };
  const int level = skeleton.m.level;
  const MacroCells& cells = *skeleton.cells;
  MacroTriangles m;
  m.level = level;
  m.corners = skeleton.m.corners;
  m.across = skeleton.m.across;
  // Each vertex's cell, as it is asked for: its parents' first (they are of lower levels).
  std::vector<Cell> cell(static_cast<std::size_t>(mesh.vertex_slots()));
  std::vector<VertexHandle> pending;
  const auto cell_of = [&](VertexHandle v) -> const Cell& {
    pending.push_back(v);
    while (!pending.empty()) {
      const VertexHandle u = pending.back();
      Cell& here = cell[static_cast<std::size_t>(u.idx)];
      if (here.kind == Cell::none && mesh.level(u) <= level) here = {Cell::on_vertex, number_of(u), -1, -1};
      if (here.kind != Cell::none) {
        pending.pop_back();
        continue;
      }
      const auto& p = mesh.parents(u);
      const Cell &a = cell[static_cast<std::size_t>(p[0].idx)], &b = cell[static_cast<std::size_t>(p[1].idx)];
      if (a.kind == Cell::none) {
        pending.push_back(p[0]);
      } else if (b.kind == Cell::none) {
        pending.push_back(p[1]);
      } else {
        here = cells.join(a, b);
        pending.pop_back();
      }
    }
    return cell[static_cast<std::size_t>(v.idx)];
  };
  m.of_triangle.assign(static_cast<std::size_t>(mesh.triangle_slots()), -1);
  m.triangles.assign(m.corners.size(), 0);
  auto& placed = skeleton.placed;
  if (name != nullptr && placed.size() < static_cast<std::size_t>(mesh.triangle_slots()))
    placed.resize(static_cast<std::size_t>(mesh.triangle_slots()));
  for (const TriangleHandle t : mesh.triangles()) {
    if (mesh.level(t) < level) continue;
    const auto c = mesh.triangle_vertices(t);
    std::array<VertexName, 3> corner{};
    if (name != nullptr) {
      for (int k = 0; k < 3; ++k) corner[k] = (*name)[static_cast<std::size_t>(c[k].idx)];
      const Placed& known = placed[static_cast<std::size_t>(t.idx)];
      if (known.face >= 0 && known.corner == corner) {
        m.of_triangle[t.idx] = known.face;
        ++m.triangles[static_cast<std::size_t>(known.face)];
        continue;
      }
    }
    const Cell joined = cells.join(cells.join(cell_of(c[0]), cell_of(c[1])), cell_of(c[2]));
    if (joined.kind != Cell::in_face)
      throw std::logic_error("macro_triangles: triangle " + std::to_string(t.idx) + " lies on a macro edge");
    if (name != nullptr) placed[static_cast<std::size_t>(t.idx)] = {corner, joined.face};
    m.of_triangle[t.idx] = joined.face;
    ++m.triangles[static_cast<std::size_t>(joined.face)];
  }
  return m;
}

MacroTriangles cells_at(const RgbMesh& mesh, const UniformMesh& uniform) {
  return place_in(mesh, *skeleton_of(uniform));
}

// The largest part's weight relative to an even share.
double imbalance_of(const std::vector<std::int32_t>& part_of, const std::vector<std::size_t>& weights, int parts) {
  std::vector<std::size_t> w(static_cast<std::size_t>(parts), 0);
  for (std::size_t f = 0; f < weights.size(); ++f) w[static_cast<std::size_t>(part_of[f])] += weights[f];
  const double total = static_cast<double>(std::accumulate(w.begin(), w.end(), std::size_t{0}));
  return total > 0 ? static_cast<double>(*std::max_element(w.begin(), w.end())) * parts / total : 1.0;
}

// METIS's partition of a graph given in compressed rows, weighted (at least 1 each).
Partition partition_graph(const std::vector<std::size_t>& weights, const std::vector<idx_t>& xadj,
                          const std::vector<idx_t>& adjncy, int parts, const char* what) {
  const std::size_t n = weights.size();
  if (parts < 1 || static_cast<std::size_t>(parts) > n)
    throw std::invalid_argument(std::string("partition: ") + std::to_string(parts) + " parts of " + std::to_string(n) +
                                " " + what);
  Partition p;
  p.parts = parts;
  p.part_of.assign(n, 0);
  if (parts > 1) {
    std::vector<idx_t> vwgt(n), part(n);
    for (std::size_t f = 0; f < n; ++f) vwgt[f] = static_cast<idx_t>(std::max<std::size_t>(1, weights[f]));
    idx_t vertices = static_cast<idx_t>(n), constraints = 1, nparts = parts, cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // the same partition on every process and run
    options[METIS_OPTION_NUMBERING] = 0;
    const auto run = [&](auto metis) {
      const int status = metis(&vertices, &constraints, const_cast<idx_t*>(xadj.data()),
                               const_cast<idx_t*>(adjncy.data()), vwgt.data(), nullptr, nullptr, &nparts, nullptr,
                               nullptr, options, &cut, part.data());
      if (status != METIS_OK) throw std::runtime_error("partition: METIS failed (status " + std::to_string(status) + ")");
    };
    run(METIS_PartGraphKway);
    p.part_of.assign(part.begin(), part.end());
    // k-way coarsening merges heavy vertices, and on a peak's few heavy macro triangles it can
    // miss the balance by 40% (1.39 for 3 parts where bisection gives 1.06): then recursive
    // bisection is tried too and the better balance kept (deterministic either way).
    if (imbalance_of(p.part_of, weights, parts) > 1.05) {
      run(METIS_PartGraphRecursive);
      std::vector<std::int32_t> bisected(part.begin(), part.end());
      if (imbalance_of(bisected, weights, parts) < imbalance_of(p.part_of, weights, parts)) p.part_of = std::move(bisected);
    }
  }
  p.weight.assign(static_cast<std::size_t>(parts), 0);
  for (std::size_t f = 0; f < n; ++f) p.weight[static_cast<std::size_t>(p.part_of[f])] += weights[f];
  const double total = static_cast<double>(std::accumulate(p.weight.begin(), p.weight.end(), std::size_t{0}));
  const double largest = static_cast<double>(*std::max_element(p.weight.begin(), p.weight.end()));
  p.imbalance = total > 0 ? largest * parts / total : 1.0;
  return p;
}

}  // namespace

namespace {

void require_floor(const RgbMesh& mesh, int level) {
  for (const TriangleHandle t : mesh.triangles()) {
    if (mesh.level(t) < level)
      throw std::invalid_argument("macro_triangles: triangle " + std::to_string(t.idx) + " is at level " +
                                  std::to_string(mesh.level(t)) + ", below the macro level " + std::to_string(level) +
                                  " (refine to a floor first: adapt --min-level)");
  }
}

}  // namespace

MacroTriangles macro_triangles(const RgbMesh& mesh, int level) {
  require_floor(mesh, level);
  return cells_at(mesh, uniform_at_floor(mesh, level));
}

Partition partition(const MacroTriangles& macro, int parts) {
  std::vector<idx_t> xadj{0}, adjncy;
  for (const auto& across : macro.across) {
    for (const std::int32_t g : across)
      if (g >= 0) adjncy.push_back(g);
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  return partition_graph(macro.triangles, xadj, adjncy, parts, "macro triangles");
}

// The floor's uniform mesh of a run, made once from a mesh holding the whole floor and used
// for every later mesh of the run whatever part of the floor it holds: the views of a
// distributed mesh hold the floor only near their part (local_view.hpp). Its vertices are
// numbered by their own slots in the kept mesh and found from a mesh's vertices by their names
// (canonical.hpp), which do not depend on slots.
struct FloorCache {
  int floor = -1;
  std::optional<UniformMesh> uniform;  // slot: its own slots
  std::unique_ptr<MacroSkeleton> skeleton;
  std::unordered_map<VertexName, std::int32_t> vertex_of_name;
  // locate_units' lookups of the units last asked for (a distributed run asks with the same
  // units several times a cycle, and a run that coarsens has one unit per cell of the floor).
  std::vector<int> units_level;
  std::vector<std::int32_t> units_cell;
  std::vector<std::pair<int, std::int32_t>> units_split;
  std::unordered_map<std::uint64_t, std::int32_t> unit_of_cell;
  std::unordered_set<std::uint64_t> split;
};

std::shared_ptr<FloorCache> make_floor_cache() { return std::make_shared<FloorCache>(); }

namespace {

// Per vertex slot of the mesh, the cached floor mesh's number of each vertex at or below the
// floor (-1 elsewhere); empty if the mesh has such a vertex that the cache does not, or holds the
// whole floor with fewer vertices than the cache (the cache is another mesh's).
std::vector<std::int32_t> floor_numbers(const RgbMesh& mesh, const std::vector<VertexName>& name, int floor,
                                        const FloorCache& cache) {
  if (!cache.uniform || cache.floor != floor) return {};
  std::vector<std::int32_t> number(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  std::size_t found = 0;
  for (const VertexHandle v : mesh.vertices()) {
    if (mesh.level(v) > floor) continue;
    const auto it = cache.vertex_of_name.find(name[static_cast<std::size_t>(v.idx)]);
    if (it == cache.vertex_of_name.end()) return {};
    number[static_cast<std::size_t>(v.idx)] = it->second;
    ++found;
  }
  if (found == cache.vertex_of_name.size()) return number;
  // Fewer: a view holding part of the floor (a triangle coarser than it), or another mesh.
  for (const TriangleHandle t : mesh.triangles())
    if (mesh.level(t) < floor) return number;
  return {};
}

void fill_floor_cache(const RgbMesh& mesh, int floor, FloorCache& cache) {
  require_floor(mesh, floor);
  cache.uniform.emplace(uniform_at_floor(mesh, floor));
  UniformMesh& u = *cache.uniform;
  const std::vector<VertexName> name = vertex_names(u.mesh);
  cache.vertex_of_name.clear();
  for (const VertexHandle v : u.mesh.vertices()) {
    u.slot[static_cast<std::size_t>(v.idx)] = v.idx;
    cache.vertex_of_name[name[static_cast<std::size_t>(v.idx)]] = v.idx;
  }
  cache.skeleton = skeleton_of(u);
  cache.floor = floor;
}

// A mesh's (or a view's) triangles placed in the cells of the uniform meshes from the floor down, the levels
// made as they are asked for (the floor's from the cache). Without a cache the mesh must hold
// the whole floor; with one, any part of it.
class CellLevels {
 public:
  CellLevels(const RgbMesh& mesh, int floor, FloorCache* cache) : mesh_(mesh), floor_(floor), cache_(cache) {
    if (cache == nullptr) {
      require_floor(mesh, floor);
      own_floor_.emplace(uniform_at_floor(mesh, floor));
      uniform_.push_back(&*own_floor_);
      at_.push_back(cells_at(mesh, *own_floor_));
      return;
    }
    name_ = vertex_names(mesh);
    floor_number_ = floor_numbers(mesh, name_, floor, *cache);
    if (floor_number_.empty()) {
      fill_floor_cache(mesh, floor, *cache);
      floor_number_ = floor_numbers(mesh, name_, floor, *cache);
    }
    uniform_.push_back(nullptr);  // (made when a level below the floor is asked for)
    at_.push_back(place_in(mesh, *cache->skeleton, floor_number_, &name_));
  }
  // The cells of `level` (at or below the floor).
  const MacroTriangles& at(int level) {
    while (static_cast<int>(at_.size()) <= level - floor_) {
      if (child_.empty()) {
        child_.reserve(static_cast<std::size_t>(mesh_.num_vertices()));
        for (const VertexHandle v : mesh_.vertices())
          if (mesh_.level(v) > 0) child_[edge_key(mesh_.parents(v)[0].idx, mesh_.parents(v)[1].idx)] = v.idx;
      }
      if (uniform_[0] == nullptr) {
        // The cached floor mesh with its vertices named by this mesh's slots (those it lacks
        // by numbers of their own), as the levels below name theirs.
        std::vector<std::int32_t> slot(cache_->uniform->slot.size());
        for (std::int32_t& s : slot) s = next_missing_--;
        for (const VertexHandle v : mesh_.vertices())
          if (mesh_.level(v) <= floor_)
            slot[static_cast<std::size_t>(floor_number_[static_cast<std::size_t>(v.idx)])] = v.idx;
        own_floor_.emplace(UniformMesh{floor_, cache_->uniform->mesh, std::move(slot)});
        uniform_[0] = &*own_floor_;
      }
      below_.push_back(std::make_unique<UniformMesh>(uniform_below(*uniform_.back(), child_, next_missing_)));
      uniform_.push_back(below_.back().get());
      at_.push_back(cells_at(mesh_, *uniform_.back()));
    }
    return at_[static_cast<std::size_t>(level - floor_)];
  }

 private:
  const RgbMesh& mesh_;
  int floor_;
  FloorCache* cache_;
  std::vector<VertexName> name_;            // with a cache: the mesh's vertex names
  std::vector<std::int32_t> floor_number_;  // with a cache: floor_numbers
  std::optional<UniformMesh> own_floor_;
  std::vector<const UniformMesh*> uniform_;
  std::vector<std::unique_ptr<UniformMesh>> below_;
  std::deque<MacroTriangles> at_;  // (a deque: the levels handed out stay where they are)
  std::unordered_map<std::uint64_t, std::int32_t> child_;
  std::int32_t next_missing_ = -2;
};

}  // namespace

Units units(const RgbMesh& mesh, int floor, int parts, double share, FloorCache* cache) {
  if (!(share > 0)) throw std::invalid_argument("units: the share must be positive");
  Units u;
  const double limit = share * static_cast<double>(mesh.num_triangles()) / std::max(1, parts);
  // Each triangle's cell at every level from the floor down to the finest (-1 where coarser),
  // from the uniform meshes of those levels: the floor's coarsened from the mesh, each next one
  // refined from the one above.
  CellLevels cells(mesh, floor, cache);
  const MacroTriangles& at_floor = cells.at(floor);
  const int finest = mesh.max_level();
  // Top-down: a unit heavier than the limit whose triangles are all finer than it splits into
  // the cells one level down that hold them.
  struct Pending {
    int level;
    std::int32_t cell;
    std::vector<TriangleHandle> triangles;
  };
  std::vector<Pending> todo;
  {
    std::vector<std::vector<TriangleHandle>> by_cell(at_floor.corners.size());
    for (const TriangleHandle t : mesh.triangles()) by_cell[static_cast<std::size_t>(at_floor.of_triangle[t.idx])].push_back(t);
    for (std::size_t f = 0; f < by_cell.size(); ++f)
      todo.push_back({floor, static_cast<std::int32_t>(f), std::move(by_cell[f])});
  }
  u.of_triangle.assign(static_cast<std::size_t>(mesh.triangle_slots()), -1);
  while (!todo.empty()) {
    Pending p = std::move(todo.back());
    todo.pop_back();
    bool split = static_cast<double>(p.triangles.size()) > limit && p.level < finest;
    for (const TriangleHandle t : p.triangles) split = split && mesh.level(t) > p.level;
    if (split) {
      const MacroTriangles& below = cells.at(p.level + 1);
      std::vector<std::pair<std::int32_t, std::vector<TriangleHandle>>> children;
      for (const TriangleHandle t : p.triangles) {
        const std::int32_t c = below.of_triangle[t.idx];
        auto it = std::find_if(children.begin(), children.end(), [c](const auto& x) { return x.first == c; });
        if (it == children.end()) it = children.insert(children.end(), {c, {}});
        it->second.push_back(t);
      }
      for (auto& [c, triangles] : children) todo.push_back({p.level + 1, c, std::move(triangles)});
      continue;
    }
    const auto id = static_cast<std::int32_t>(u.level.size());
    u.level.push_back(p.level);
    u.cell.push_back(p.cell);
    u.triangles.push_back(p.triangles.size());
    for (const TriangleHandle t : p.triangles) u.of_triangle[t.idx] = id;
  }
  // Units are neighbours where their triangles share an edge.
  std::vector<std::vector<std::int32_t>> next(u.level.size());
  for (const TriangleHandle t : mesh.triangles()) {
    const std::int32_t a = u.of_triangle[t.idx];
    for (const EdgeHandle e : mesh.triangle_edges(t)) {
      if (mesh.is_boundary(e)) continue;
      const std::int32_t b = u.of_triangle[mesh.other_triangle(e, t).idx];
      if (b != a) next[static_cast<std::size_t>(a)].push_back(b);
    }
  }
  u.neighbours.resize(next.size());
  for (std::size_t a = 0; a < next.size(); ++a) {
    std::sort(next[a].begin(), next[a].end());
    next[a].erase(std::unique(next[a].begin(), next[a].end()), next[a].end());
    u.neighbours[a] = std::move(next[a]);
  }
  return u;
}

namespace {

std::uint64_t cell_key(int level, std::int32_t cell) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(level)) << 32) | static_cast<std::uint32_t>(cell);
}

// Each triangle's unit: down from its floor cell through the split cells. (The floor's cells
// in an array: in a run that coarsens they are all the units, and this runs several times a
// cycle.)
// (units: the units' levels, cells and divided cells, which unit_of_cell and split look up.)
std::vector<std::int32_t> walk_to_units(const RgbMesh& view, int floor, CellLevels& cells, const Units& units,
                                        const std::unordered_map<std::uint64_t, std::int32_t>& unit_of_cell,
                                        const std::unordered_set<std::uint64_t>& split) {
  const MacroTriangles& at_floor = cells.at(floor);
  std::vector<std::int32_t> unit_at_floor(at_floor.corners.size(), -1);
  std::vector<char> split_at_floor(at_floor.corners.size(), 0);
  for (std::size_t k = 0; k < units.level.size(); ++k)
    if (units.level[k] == floor) unit_at_floor[static_cast<std::size_t>(units.cell[k])] = static_cast<std::int32_t>(k);
  for (const auto& [level, cell] : units.split)
    if (level == floor) split_at_floor[static_cast<std::size_t>(cell)] = 1;
  std::vector<std::int32_t> out(static_cast<std::size_t>(view.triangle_slots()), -1);
  for (const TriangleHandle t : view.triangles()) {
    if (view.level(t) < floor) continue;
    const std::int32_t f = at_floor.of_triangle[static_cast<std::size_t>(t.idx)];
    if (f < 0) continue;
    if (unit_at_floor[static_cast<std::size_t>(f)] >= 0) {
      out[static_cast<std::size_t>(t.idx)] = unit_at_floor[static_cast<std::size_t>(f)];
      continue;
    }
    if (!split_at_floor[static_cast<std::size_t>(f)]) continue;
    for (int level = floor + 1;; ++level) {
      if (view.level(t) < level) break;  // coarser than the cells here: no unit
      const std::int32_t c = cells.at(level).of_triangle[static_cast<std::size_t>(t.idx)];
      if (c < 0) break;
      const std::uint64_t key = cell_key(level, c);
      if (const auto it = unit_of_cell.find(key); it != unit_of_cell.end()) {
        out[static_cast<std::size_t>(t.idx)] = it->second;
        break;
      }
      if (!split.count(key)) break;
    }
  }
  return out;
}

}  // namespace

Units shared_units(const RgbMesh& view, int floor, int parts, const std::vector<char>& counted, const Collectives& all,
                   FloorCache* cache, double share) {
  if (!(share > 0)) throw std::invalid_argument("shared_units: the share must be positive");
  if (counted.size() != static_cast<std::size_t>(view.triangle_slots()))
    throw std::invalid_argument("shared_units: one flag per triangle slot is needed");
  CellLevels cells(view, floor, cache);
  std::vector<TriangleHandle> mine;
  std::uint64_t finest_here = 0;
  for (const TriangleHandle t : view.triangles())
    if (counted[static_cast<std::size_t>(t.idx)]) {
      mine.push_back(t);
      finest_here = std::max<std::uint64_t>(finest_here, static_cast<std::uint64_t>(view.level(t)));
    }
  std::uint64_t total = mine.size();
  all.sum(&total, 1);
  const std::vector<std::uint64_t> finest_each = all.all_gather({finest_here});
  const int finest = static_cast<int>(*std::max_element(finest_each.begin(), finest_each.end()));
  const double limit = share * static_cast<double>(total) / std::max(1, parts);
  // Level by level from the floor: the cells still to decide, the same list on every process;
  // a cell heavier than the limit whose triangles are all finer than it divides into the cells
  // one level down that hold them (as in units()).
  Units u;
  std::unordered_map<std::uint64_t, std::int32_t> unit_of_cell;
  std::unordered_set<std::uint64_t> split;
  std::vector<std::int32_t> pending(cells.at(floor).corners.size());
  std::iota(pending.begin(), pending.end(), 0);
  for (int level = floor; !pending.empty(); ++level) {
    const MacroTriangles& here = cells.at(level);
    std::vector<std::int32_t> position(here.corners.size(), -1);
    for (std::size_t k = 0; k < pending.size(); ++k) position[static_cast<std::size_t>(pending[k])] = static_cast<std::int32_t>(k);
    // Per pending cell: its triangles, and those not finer than it.
    std::vector<std::uint64_t> count(2 * pending.size(), 0);
    for (const TriangleHandle t : mine) {
      if (view.level(t) < level) continue;  // in a cell decided above
      const std::int32_t c = here.of_triangle[static_cast<std::size_t>(t.idx)];
      if (c < 0 || position[static_cast<std::size_t>(c)] < 0) continue;
      const auto k = static_cast<std::size_t>(position[static_cast<std::size_t>(c)]);
      ++count[2 * k];
      if (view.level(t) <= level) ++count[2 * k + 1];
    }
    all.sum(count.data(), count.size());
    std::vector<std::uint64_t> next_here;
    for (std::size_t k = 0; k < pending.size(); ++k) {
      const std::uint64_t key = cell_key(level, pending[k]);
      const bool divide = static_cast<double>(count[2 * k]) > limit && level < finest && count[2 * k + 1] == 0;
      if (!divide) {
        unit_of_cell[key] = static_cast<std::int32_t>(u.level.size());
        u.level.push_back(level);
        u.cell.push_back(pending[k]);
        u.triangles.push_back(count[2 * k]);
        continue;
      }
      split.insert(key);
      u.split.emplace_back(level, pending[k]);
    }
    if (u.split.empty() || u.split.back().first != level) break;
    // The cells one level down that hold triangles of the divided cells, from every process.
    const MacroTriangles& below = cells.at(level + 1);
    for (const TriangleHandle t : mine) {
      const std::int32_t c = here.of_triangle[static_cast<std::size_t>(t.idx)];
      if (view.level(t) <= level || c < 0 || !split.count(cell_key(level, c))) continue;
      next_here.push_back(static_cast<std::uint64_t>(below.of_triangle[static_cast<std::size_t>(t.idx)]));
    }
    std::sort(next_here.begin(), next_here.end());
    next_here.erase(std::unique(next_here.begin(), next_here.end()), next_here.end());
    std::vector<std::uint64_t> next = all.all_gather(next_here);
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    pending.assign(next.begin(), next.end());
  }
  u.of_triangle = walk_to_units(view, floor, cells, u, unit_of_cell, split);
  // Neighbours: across the edges of the counted triangles (their neighbours are exact too),
  // from every process.
  std::vector<std::uint64_t> pairs;
  for (const TriangleHandle t : mine) {
    const std::int32_t a = u.of_triangle[static_cast<std::size_t>(t.idx)];
    for (const EdgeHandle e : view.triangle_edges(t)) {
      if (view.is_boundary(e)) continue;
      const std::int32_t b = u.of_triangle[static_cast<std::size_t>(view.other_triangle(e, t).idx)];
      if (a >= 0 && b >= 0 && a != b) pairs.push_back(edge_key(a, b));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  u.neighbours.assign(u.level.size(), {});
  for (const std::uint64_t pair : all.all_gather(pairs)) {
    const auto a = static_cast<std::int32_t>(pair >> 32), b = static_cast<std::int32_t>(pair & 0xffffffffu);
    u.neighbours[static_cast<std::size_t>(a)].push_back(b);
    u.neighbours[static_cast<std::size_t>(b)].push_back(a);
  }
  for (auto& n : u.neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return u;
}

std::vector<std::int32_t> locate_units(const RgbMesh& view, int floor, const Units& units, FloorCache* cache) {
  CellLevels cells(view, floor, cache);
  const auto lookups = [&units](std::unordered_map<std::uint64_t, std::int32_t>& unit_of_cell,
                                std::unordered_set<std::uint64_t>& split) {
    unit_of_cell.clear();
    split.clear();
    for (std::size_t k = 0; k < units.level.size(); ++k)
      unit_of_cell[cell_key(units.level[k], units.cell[k])] = static_cast<std::int32_t>(k);
    for (const auto& [level, cell] : units.split) split.insert(cell_key(level, cell));
  };
  if (cache == nullptr) {
    std::unordered_map<std::uint64_t, std::int32_t> unit_of_cell;
    std::unordered_set<std::uint64_t> split;
    lookups(unit_of_cell, split);
    return walk_to_units(view, floor, cells, units, unit_of_cell, split);
  }
  if (cache->units_level != units.level || cache->units_cell != units.cell || cache->units_split != units.split) {
    lookups(cache->unit_of_cell, cache->split);
    cache->units_level = units.level;
    cache->units_cell = units.cell;
    cache->units_split = units.split;
  }
  return walk_to_units(view, floor, cells, units, cache->unit_of_cell, cache->split);
}

Partition partition(const Units& units, int parts) {
  std::vector<idx_t> xadj{0}, adjncy;
  for (const auto& n : units.neighbours) {
    adjncy.insert(adjncy.end(), n.begin(), n.end());
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  return partition_graph(units.triangles, xadj, adjncy, parts, "units");
}

std::vector<std::int32_t> triangle_parts(const RgbMesh& mesh, const fem::SurfaceMesh& fe, int floor, int parts,
                                         FloorCache* cache) {
  const Units u = units(mesh, floor, parts, 0.1, cache);
  const Partition p = partition(u, std::min<int>(parts, static_cast<int>(u.level.size())));
  std::vector<std::int32_t> out(fe.triangle.size());
  for (std::size_t t = 0; t < fe.triangle.size(); ++t)
    out[t] = p.part_of[static_cast<std::size_t>(u.of_triangle[fe.triangle[t].idx])];
  return out;
}

Partition partition_rows(const fem::SparseMatrix& a, int parts) {
  if (!a.isCompressed()) throw std::invalid_argument("partition_rows: the matrix must be compressed");
  const auto n = static_cast<std::size_t>(a.outerSize());
  std::vector<idx_t> xadj{0}, adjncy;
  adjncy.reserve(static_cast<std::size_t>(a.nonZeros()));
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = a.outerIndexPtr()[i]; k < a.outerIndexPtr()[i + 1]; ++k)
      if (static_cast<std::size_t>(a.innerIndexPtr()[k]) != i) adjncy.push_back(a.innerIndexPtr()[k]);
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  return partition_graph(std::vector<std::size_t>(n, 1), xadj, adjncy, parts, "rows");
}

int macro_level_for(const RgbMesh& mesh, int parts, int min_level, int per_part) {
  int level = std::max(0, min_level);
  while (level < kMaxLevel &&
         uniform_level_counts(mesh, level).triangles < static_cast<double>(parts) * static_cast<double>(per_part))
    ++level;
  return level;
}

}  // namespace rgbmesh::parallel
