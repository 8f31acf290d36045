// rgbmesh::parallel::distribute_mesh (distributed_mesh.hpp). Written against the collectives
// of collectives.hpp, without MPI of its own.

#include "rgbmesh/parallel/distributed_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "collectives.hpp"
#include "rgbmesh/canonical.hpp"
#include "rgbmesh/parallel/local_view.hpp"
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/partition.hpp"

namespace rgbmesh::parallel {

namespace {

// Two layers of neighbours around a part: the first layer's vertices then have their whole
// stars, so their limit positions are the whole mesh's (the estimators read the first layer:
// the neighbours across an edge, the triangles around a corner).
constexpr int kGhostLayers = 2;
// How coarse a view is away from its part and ghost layers: as coarse as the RGB rules allow,
// down to the base mesh, not only to the run's floor. The floor is the whole mesh's (no
// triangle coarser than --min-level); a view's rest only has to join its layers conformingly.
// A view that kept the floor whole held 0.88 of the mesh on two processes (the moving peak at
// --min-level 6, where the floor is two thirds of the mesh): every pass over it cost nearly
// one process's pass over the whole mesh.
constexpr int kViewFloor = 0;

// A P2 edge node's name: its edge's midpoint vertex's name with bit 62 flipped, so that it
// differs from every vertex of the same finite-element mesh.
VertexName edge_node_name(VertexName a, VertexName b) { return child_name(a, b) ^ (VertexName{1} << 62); }

// A vertex handed to another process: its name, its parents' names, its level.
struct Travelling {
  VertexName name = 0, a = 0, b = 0;
  std::uint64_t level = 0;
};

void append(std::vector<std::uint64_t>& out, const Travelling& t) { out.insert(out.end(), {t.name, t.a, t.b, t.level}); }
std::vector<Travelling> unpack(const std::vector<std::uint64_t>& in) {
  std::vector<Travelling> out;
  for (std::size_t i = 0; i + 3 < in.size(); i += 4) out.push_back({in[i], in[i + 1], in[i + 2], in[i + 3]});
  return out;
}

// Vertex slots by name: open addressing with linear probing, at most half full, in two flat
// arrays (12 bytes a place). Names are hashes already except the base mesh's (their slots),
// so a multiplication spreads them. Built for the whole view several times a step, where a
// std::unordered_map of a view's 800,000 vertices took 0.4-0.5 s (a node allocated each).
class SlotByName {
 public:
  explicit SlotByName(std::size_t expected) { reset(expected); }
  void set(VertexName n, std::int32_t slot) {
    if (2 * (count_ + 1) > slot_.size()) {
      const std::vector<VertexName> key = std::move(key_);
      const std::vector<std::int32_t> was = std::move(slot_);
      reset(2 * count_ + 2);
      for (std::size_t i = 0; i < was.size(); ++i)
        if (was[i] >= 0) set(key[i], was[i]);
    }
    std::size_t i = home(n);
    while (slot_[i] >= 0 && key_[i] != n) i = (i + 1) & mask_;
    if (slot_[i] < 0) ++count_;
    key_[i] = n;
    slot_[i] = slot;
  }
  std::int32_t get(VertexName n) const {
    for (std::size_t i = home(n);; i = (i + 1) & mask_) {
      if (slot_[i] < 0) return -1;
      if (key_[i] == n) return slot_[i];
    }
  }

 private:
  void reset(std::size_t expected) {
    std::size_t places = 16;
    int bits = 4;
    while (places < 2 * expected) places *= 2, ++bits;
    key_.assign(places, 0);
    slot_.assign(places, -1);
    mask_ = places - 1;
    shift_ = 64 - bits;
    count_ = 0;
  }
  std::size_t home(VertexName n) const { return static_cast<std::size_t>((n * 0x9E3779B97F4A7C15ull) >> shift_); }
  std::vector<VertexName> key_;
  std::vector<std::int32_t> slot_;
  std::size_t mask_ = 0, count_ = 0;
  int shift_ = 60;
};

// The view's vertices by name, kept current while vertices are inserted (an insertion
// observer, for as long as it lives); `inserted` lists the new ones.
class Names {
 public:
  explicit Names(RgbMesh& view) : view_(view), name_(vertex_names(view)), at_(view.num_vertices()) {
    for (const VertexHandle v : view.vertices()) at_.set(name_[static_cast<std::size_t>(v.idx)], v.idx);
    id_ = view.add_insertion_observer([this](VertexHandle v, VertexHandle a, VertexHandle b) {
      if (name_.size() < static_cast<std::size_t>(view_.vertex_slots())) name_.resize(static_cast<std::size_t>(view_.vertex_slots()), 0);
      const VertexName n = child_name(name_[static_cast<std::size_t>(a.idx)], name_[static_cast<std::size_t>(b.idx)]);
      name_[static_cast<std::size_t>(v.idx)] = n;
      at_.set(n, v.idx);
      inserted.push_back(v);
    });
  }
  ~Names() { view_.remove_observer(id_); }
  Names(const Names&) = delete;
  Names& operator=(const Names&) = delete;

  VertexHandle find(VertexName n) const {
    const VertexHandle v(at_.get(n));
    return v.valid() && view_.alive(v) ? v : VertexHandle();
  }
  VertexName of(VertexHandle v) const { return name_[static_cast<std::size_t>(v.idx)]; }
  Travelling travelling(VertexHandle v) const {
    const auto& p = view_.parents(v);
    return {of(v), of(p[0]), of(p[1]), static_cast<std::uint64_t>(view_.level(v))};
  }
  std::vector<VertexHandle> inserted;

 private:
  RgbMesh& view_;
  std::vector<VertexName> name_;
  SlotByName at_;
  int id_ = -1;
};

// Inserts the vertices, parents first, each with split_edge on the edge between its parents
// (forced splits insert what the RGB rules need with it); again while any goes in. Returns
// those whose parents' edge never appeared.
std::vector<Travelling> insert(RgbMesh& view, const Names& names, std::vector<Travelling> items) {
  std::sort(items.begin(), items.end(), [](const Travelling& x, const Travelling& y) { return x.level < y.level; });
  for (bool progress = true; progress && !items.empty();) {
    progress = false;
    std::vector<Travelling> left;
    for (const Travelling& t : items) {
      if (names.find(t.name).valid()) continue;
      const VertexHandle a = names.find(t.a), b = names.find(t.b);
      const EdgeHandle e = a.valid() && b.valid() ? view.find_edge(a, b) : EdgeHandle();
      if (!e.valid() || view.is_red(e)) {
        left.push_back(t);
        continue;
      }
      view.split_edge(e);
      progress = true;
    }
    items = std::move(left);
  }
  return items;
}

// The corners of the triangles flagged, and of `layers` layers of triangles around them.
std::vector<char> corners_and_layers(const RgbMesh& view, const std::vector<std::int32_t>& part, std::int32_t me, int layers) {
  std::vector<char> in(static_cast<std::size_t>(view.vertex_slots()), 0);
  for (const TriangleHandle t : view.triangles())
    if (part[static_cast<std::size_t>(t.idx)] == me)
      for (const VertexHandle v : view.triangle_vertices(t)) in[static_cast<std::size_t>(v.idx)] = 1;
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<char> next = in;
    for (const TriangleHandle t : view.triangles()) {
      const auto c = view.triangle_vertices(t);
      if (in[static_cast<std::size_t>(c[0].idx)] || in[static_cast<std::size_t>(c[1].idx)] || in[static_cast<std::size_t>(c[2].idx)])
        for (const VertexHandle v : c) next[static_cast<std::size_t>(v.idx)] = 1;
    }
    in = std::move(next);
  }
  return in;
}

// Removes these vertices of the view, finest first (a vertex's finer neighbours among them go
// before it), as far as they can go. Returns those removed.
std::vector<VertexHandle> remove_finest_first(RgbMesh& view, std::vector<VertexHandle> vertices) {
  std::sort(vertices.begin(), vertices.end(),
            [&view](VertexHandle a, VertexHandle b) { return view.level(a) > view.level(b); });
  std::vector<VertexHandle> out;
  for (bool removed = true; removed;) {
    removed = false;
    for (const VertexHandle v : vertices)
      if (view.alive(v) && view.is_removable(v)) {
        view.remove_vertex(v);
        out.push_back(v);
        removed = true;
      }
  }
  return out;
}

void add_unique(std::vector<std::int32_t>& set, std::int32_t x) {
  if (std::find(set.begin(), set.end(), x) == set.end()) set.push_back(x);
}

// A set of names kept for a whole cycle, as one sorted array (8 bytes a name, where a hash
// set takes about 40: these sets span the view and are alive during the solve, the run's
// peak), with the names added since it was made in a small hash set beside it.
class NameSet {
 public:
  void assign(std::vector<VertexName> names) {
    std::sort(names.begin(), names.end());
    sorted_ = std::move(names);
    sorted_.shrink_to_fit();
    added_.clear();
  }
  bool contains(VertexName n) const {
    return std::binary_search(sorted_.begin(), sorted_.end(), n) || (!added_.empty() && added_.count(n) != 0);
  }
  void insert(VertexName n) {
    if (!contains(n)) added_.insert(n);
  }
  // The slots whose names are not in the set, of (name, slot) pairs sorted by name: one walk
  // along both, where a binary search per vertex took 0.5-0.8 s on a view of 800,000.
  std::vector<std::int32_t> absent(const std::vector<std::pair<VertexName, std::int32_t>>& by_name) const {
    std::vector<std::int32_t> out;
    auto known = sorted_.begin();
    for (const auto& [n, slot] : by_name) {
      while (known != sorted_.end() && *known < n) ++known;
      if (known != sorted_.end() && *known == n) continue;
      if (!added_.empty() && added_.count(n) != 0) continue;
      out.push_back(slot);
    }
    return out;
  }

 private:
  std::vector<VertexName> sorted_;
  std::unordered_set<VertexName> added_;
};

class DistributedMesh {
 public:
  // share: shared_units' limit on a unit's triangles before it is divided; infinite (the
  // floor's cells as units) for runs that coarsen, whose triangles must stay inside one unit.
  DistributedMesh(int floor, int parts, int me, double share, double compact_below)
      : floor_(floor), parts_(parts), me_(me), share_(share), compact_below_(compact_below) {}

  // ---- the start of a cycle: parts, migration, the view coarsened away from its part ----
  void prepare(RgbMesh& view) {
    std::vector<char> counted(static_cast<std::size_t>(view.triangle_slots()), 0);
    std::vector<std::int32_t> part;
    if (!whole_) part = parts_of(view);
    if (!whole_ && parts_still_balanced(view, part)) {
      // The parts stay: the views' ghost layers are already exact (the coarsening rounds
      // made them so, the splits were reconciled), so nothing migrates; only what the
      // refinement forced beyond the layers goes.
      if (coarsen_away(view, own_of(part), kViewFloor, kGhostLayers) > 0) part = parts_of(view);
      if (view.live_fraction() < compact_below_) {
        view.compact();
        part = parts_of(view);
      }
      survey(view, part);
      return;
    }
    if (whole_) {
      // Every process holds the whole mesh: rank 0 counts it.
      if (me_ == 0)
        for (const TriangleHandle t : view.triangles()) counted[static_cast<std::size_t>(t.idx)] = 1;
    } else {
      for (const TriangleHandle t : view.triangles()) counted[static_cast<std::size_t>(t.idx)] = part[static_cast<std::size_t>(t.idx)] == me_;
    }
    units_ =
        shared_units(view, floor_, parts_, counted, {detail::sum, detail::all_gather}, cache_.get(), share_);
    const Partition parted = partition(units_, std::min<int>(parts_, static_cast<int>(units_.level.size())));
    unit_part_ = parted.part_of;
    partitioned_imbalance_ = parted.imbalance;
    if (!whole_) {
      // The new parts, where shared_units just placed the view's triangles.
      const auto new_parts = [&] {
        part.assign(units_.of_triangle.size(), -1);
        for (std::size_t t = 0; t < part.size(); ++t)
          part[t] =
              units_.of_triangle[t] >= 0 ? unit_part_[static_cast<std::size_t>(units_.of_triangle[t])] : -1;
      };
      new_parts();
      if (relabel_to_stay(counted, part)) new_parts();
      migrate(view, counted, part, true);
    }
    whole_ = false;
    canonical_diagonals(view);
    coarsen_away(view, own_triangles(view), kViewFloor, kGhostLayers);
    // A view that shrank (a moving feature left its part, or its part moved) gives its free
    // slots back, as a serial run's mesh does at the start of a cycle: every pass over the
    // view costs its slots, not its vertices (a view of 42,000 vertices kept a million
    // triangle slots from the settling step). Compaction keeps the live elements' order, so
    // the units and parts are the same; the floor cache sees the new slots and is made again.
    if (view.live_fraction() < compact_below_) view.compact();
    survey(view, parts_of(view));
  }

  // ---- a stage's removals (RefinementOptions::coarsen): each process removes the candidates
  // among its own triangles' corners, whose stars and neighbours it holds exactly, as far as
  // its view lets them go (a removal's neighbours are tried again at once); then the
  // ghost layers are made exact again (the others' removals), and again, until no process has a
  // candidate. Removals never make another candidate unremovable, so this ends with the mesh
  // one process reaches in any order: no candidate left anywhere. ----
  std::uint64_t coarsen(RgbMesh& view, const LodCriterion& criterion) {
    // Candidates by this process's triangles' indicators (the criterion's vertex values are
    // the largest over the own triangles around each vertex); a vertex on an interface is one
    // only if every process around it says so.
    std::unordered_set<VertexName> candidate;
    // The lowest part around each own corner on an interface, which counts its removal (once,
    // as one process counts; elsewhere this process counts it). Constant while the rounds go
    // on: a vertex's triangles stay inside the floor's cells that hold it, and those are the
    // units of a run that coarsens.
    std::unordered_map<VertexName, std::int32_t> lowest;
    {
      const std::vector<std::int32_t> part = parts_of(view);
      const std::vector<VertexName> name = vertex_names(view);
      std::unordered_map<std::int32_t, std::vector<std::int32_t>> around;  // own corners on interfaces
      std::vector<char> own_corner(static_cast<std::size_t>(view.vertex_slots()), 0);
      for (const TriangleHandle t : view.triangles())
        if (part[static_cast<std::size_t>(t.idx)] == me_)
          for (const VertexHandle v : view.triangle_vertices(t))
            own_corner[static_cast<std::size_t>(v.idx)] = 1;
      for (const TriangleHandle t : view.triangles()) {
        const std::int32_t q = part[static_cast<std::size_t>(t.idx)];
        if (q < 0 || q == me_) continue;
        for (const VertexHandle v : view.triangle_vertices(t))
          if (own_corner[static_cast<std::size_t>(v.idx)]) add_unique(around[v.idx], q);
      }
      std::vector<std::vector<std::uint64_t>> blocked(static_cast<std::size_t>(parts_));
      for (const VertexHandle v : view.vertices()) {
        if (!own_corner[static_cast<std::size_t>(v.idx)]) continue;
        const VertexName n = name[static_cast<std::size_t>(v.idx)];
        const bool here = view.level(v) > floor_ && criterion.vertex_priority(view, v) > 0;
        // (Only the candidates are kept, and the lowest part only on interfaces: most own
        // corners are at the floor, and the rounds look every vertex of the view up.)
        if (here) candidate.insert(n);
        const auto it = around.find(v.idx);
        if (it == around.end()) continue;
        std::int32_t low = me_;
        for (const std::int32_t q : it->second) low = std::min(low, q);
        lowest[n] = low;
        if (!here)
          for (const std::int32_t q : it->second) blocked[static_cast<std::size_t>(q)].push_back(n);
      }
      for (const auto& from : detail::all_to_all(blocked))
        for (const std::uint64_t n : from) candidate.erase(n);
    }
    std::uint64_t counted = 0;
    for (;;) {
      // This round's removals: the candidates removable now (each stays removable while the
      // others go: their stars share no triangle, or the new neighbours are no finer).
      const std::vector<VertexName> name = vertex_names(view);
      std::vector<VertexHandle> go;
      for (const VertexHandle v : view.vertices()) {
        if (candidate.count(name[static_cast<std::size_t>(v.idx)]) != 0 && view.is_removable(v)) go.push_back(v);
      }
      std::uint64_t removed = 0;
      std::vector<std::uint64_t> gone;
      // A removal can make a neighbouring candidate removable (section V-A): those are
      // removed in the same round, so that rounds are needed only where a removal waits for
      // another process's.
      VertexStar star;
      for (std::size_t i = 0; i < go.size(); ++i) {
        const VertexHandle v = go[i];
        if (!view.alive(v) || !view.is_removable(v)) continue;
        const VertexName n = name[static_cast<std::size_t>(v.idx)];
        if (const auto it = lowest.find(n); it == lowest.end() || it->second == me_) ++counted;
        gone.push_back(n);
        view.star(v, star);
        view.remove_vertex(v);
        // (Whether a neighbour is removable next depends on the diagonals: by names, as in
        // one process's coarsening.)
        canonical_diagonals_near(view, name, star.neighbors);
        ++removed;
        for (const VertexHandle w : star.neighbors) {
          if (candidate.count(name[static_cast<std::size_t>(w.idx)]) != 0 && view.alive(w) && view.is_removable(w))
            go.push_back(w);
        }
      }
      detail::sum(&removed, 1);
      if (removed == 0) break;
      ++rounds_;  // (the last pass, which removed nothing, costs no exchange of the layers)
      // The ghost layers exact again: every process's removals made here too, then the
      // vertices that the grown triangles' layers need from their owners, as at the start of
      // a cycle with the same parts, and the view trimmed to two layers.
      // (A removal on an interface is counted by the lowest part around it, also where another
      // process made it first.)
      for (const VertexHandle v : remove_named(view, name, gone))
        if (const auto it = lowest.find(name[static_cast<std::size_t>(v.idx)]); it != lowest.end() && it->second == me_)
          ++counted;
      const std::vector<std::int32_t> now = parts_of(view);
      migrate(view, own_of(now), now);
      coarsen_away(view, own_triangles(view), kViewFloor, kGhostLayers);
    }
    canonical_diagonals(view);
    survey(view, parts_of(view));
    return counted;
  }

  // The coarsening rounds and the exchanges since the previous call, for the cycle's report,
  // which must be the same on every process (rank 0 writes it for all). Every process takes
  // part in each round and exchange, so a difference is a bug: it stops the run rather than
  // report one process's count. (Equal on all processes exactly when P times the sum of
  // squares is the square of the sum.)
  std::array<std::uint64_t, 2> rounds_since_last() {
    const std::uint64_t exchanged = detail::exchanges();
    const std::array<std::uint64_t, 2> mine = {rounds_ - rounds_reported_, exchanged - exchanges_reported_};
    rounds_reported_ = rounds_;
    std::uint64_t check[4] = {mine[0], mine[0] * mine[0], mine[1], mine[1] * mine[1]};
    detail::sum(check, 4);
    const auto p = static_cast<std::uint64_t>(parts_);
    if (p * check[1] != check[0] * check[0] || p * check[3] != check[2] * check[2])
      throw std::logic_error("distributed mesh: the processes counted different coarsening rounds or exchanges");
    exchanges_reported_ = exchanged;
    return mine;
  }

  // Every process's removals of a round, `gone` this one's, made in this view too where it
  // has the vertices. The view is the whole mesh less vertices that removals took away
  // (coarsen_away's), so each of them is removable here too: a removal never makes another
  // vertex unremovable. The view is then the whole mesh's less such vertices again.
  // (`name`: the view's names by slot from before this round's removals, which inserted
  // nothing.)
  // Returns the vertices removed (their slots, now free).
  std::vector<VertexHandle> remove_named(RgbMesh& view, const std::vector<VertexName>& name,
                                         const std::vector<std::uint64_t>& gone) {
    std::vector<std::vector<std::uint64_t>> to(static_cast<std::size_t>(parts_));
    for (int q = 0; q < parts_; ++q)
      if (q != me_) to[static_cast<std::size_t>(q)] = gone;
    std::unordered_set<VertexName> others;
    for (const auto& from : detail::all_to_all(to)) others.insert(from.begin(), from.end());
    std::vector<VertexHandle> here;
    if (!others.empty())
      for (const VertexHandle v : view.vertices())
        if (others.count(name[static_cast<std::size_t>(v.idx)])) here.push_back(v);
    return remove_finest_first(view, std::move(here));
  }

  // known_, region_ and neighbours_ for the view as it is now.
  // (part: parts_of(view).)
  void survey(const RgbMesh& view, const std::vector<std::int32_t>& part) {
    // (By names: the slots may change before the cycle's mesh is numbered, when limit
    // positions are computed with helper vertices that are taken out again.)
    const std::vector<VertexName> name = vertex_names(view);
    const std::vector<char> exact = corners_and_layers(view, part, me_, kGhostLayers);
    std::vector<VertexName> known, region;
    known.reserve(view.num_vertices());
    for (const VertexHandle v : view.vertices()) {
      known.push_back(name[static_cast<std::size_t>(v.idx)]);
      if (exact[static_cast<std::size_t>(v.idx)]) region.push_back(name[static_cast<std::size_t>(v.idx)]);
    }
    known_.assign(std::move(known));
    region_.assign(std::move(region));
    // The neighbours: the processes owning triangles among this one's ghost layers. Whoever
    // needs a split made here owns triangles within two layers of it, so the split's owner
    // (whose part holds it) has them among its ghost layers and hands it on.
    neighbours_.clear();
    for (const TriangleHandle t : view.triangles()) {
      const std::int32_t q = part[static_cast<std::size_t>(t.idx)];
      if (q < 0 || q == me_) continue;
      const auto c = view.triangle_vertices(t);
      if (exact[static_cast<std::size_t>(c[0].idx)] || exact[static_cast<std::size_t>(c[1].idx)] ||
          exact[static_cast<std::size_t>(c[2].idx)])
        add_unique(neighbours_, q);
    }
  }

  // ---- after an adaptation: the splits that reach other processes' parts, to a fixpoint ----
  void reconcile(RgbMesh& view) {
    Names names(view);
    std::vector<std::pair<VertexName, std::int32_t>> by_name;
    by_name.reserve(view.num_vertices());
    for (const VertexHandle v : view.vertices()) by_name.emplace_back(names.of(v), v.idx);
    std::sort(by_name.begin(), by_name.end());
    std::vector<std::int32_t> fresh_slots = known_.absent(by_name);
    std::vector<std::pair<VertexName, std::int32_t>>().swap(by_name);
    std::sort(fresh_slots.begin(), fresh_slots.end());  // (in slot order, as the view lists them)
    std::vector<VertexHandle> fresh;
    fresh.reserve(fresh_slots.size());
    for (const std::int32_t slot : fresh_slots) fresh.emplace_back(slot);
    for (;;) {
      std::sort(fresh.begin(), fresh.end(), [&view](VertexHandle a, VertexHandle b) { return view.level(a) < view.level(b); });
      // Only the splits inside the part and its ghost layers: those beyond, where the view is
      // coarser than the whole mesh, may be forced splits the whole mesh does not need (its
      // processes there make the ones it does).
      std::vector<std::uint64_t> mine;
      for (const VertexHandle v : fresh) {
        if (!view.alive(v)) continue;
        const Travelling t = names.travelling(v);
        if (!region_.contains(t.a) || !region_.contains(t.b)) continue;
        region_.insert(t.name);
        append(mine, t);
      }
      std::uint64_t made = mine.size();
      detail::sum(&made, 1);
      if (made == 0) break;
      // To the neighbours only.
      std::vector<std::vector<std::uint64_t>> to(static_cast<std::size_t>(parts_));
      for (const std::int32_t q : neighbours_) to[static_cast<std::size_t>(q)] = mine;
      std::vector<std::uint64_t>().swap(mine);
      std::vector<Travelling> wanted;
      for (const auto& from : detail::all_to_all(to))
        for (const Travelling& t : unpack(from))
          if (region_.contains(t.a) && region_.contains(t.b) && !names.find(t.name).valid())
            wanted.push_back(t);
      names.inserted.clear();
      insert(view, names, std::move(wanted));
      fresh = names.inserted;
    }
    canonical_diagonals(view);
  }

  // ---- the finite-element mesh's parts, and its unknowns numbered across processes ----
  std::vector<std::int32_t> number(const RgbMesh& view, const fem::SurfaceMesh& fe) {
    const std::size_t nt = fe.triangles.size(), nd = fe.num_dofs(), nv = fe.vertex.size();
    const std::vector<std::int32_t> part_of_slot = parts_of(view);
    const std::vector<VertexName> names = vertex_names(view);
    std::vector<std::int32_t> tp(nt);
    for (std::size_t t = 0; t < nt; ++t) tp[t] = part_of_slot[static_cast<std::size_t>(fe.triangle[t].idx)];
    dof_name_.assign(nd, 0);
    for (std::size_t d = 0; d < nv; ++d) dof_name_[d] = names[static_cast<std::size_t>(fe.vertex[d].idx)];
    // (A triangle's nodes without a heap allocation: this runs three times per triangle.)
    struct Nodes {
      std::array<std::int32_t, 6> node;
      std::size_t count;
      const std::int32_t* begin() const { return node.data(); }
      const std::int32_t* end() const { return node.data() + count; }
    };
    const auto nodes_of = [&fe](std::size_t t) {
      Nodes n{{fe.triangles[t][0], fe.triangles[t][1], fe.triangles[t][2], 0, 0, 0}, 3};
      if (fe.order == 2) {
        for (std::size_t k = 0; k < 3; ++k) n.node[3 + k] = fe.edge_nodes[t][k];
        n.count = 6;
      }
      return n;
    };
    if (fe.order == 2)
      for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
          dof_name_[static_cast<std::size_t>(fe.edge_nodes[t][k])] =
              edge_node_name(dof_name_[static_cast<std::size_t>(fe.triangles[t][k])],
                             dof_name_[static_cast<std::size_t>(fe.triangles[t][(k + 1) % 3])]);
    // Each node's parts around it, and its owner: the lowest (exact for the own triangles'
    // nodes, whose neighbours the view holds). As one array: node d's parts are
    // parts_at[at[d] .. at[d] + count[d]), sorted.
    std::vector<std::uint32_t> at(nd + 1, 0);
    std::vector<char> own_node(nd, 0);
    for (std::size_t t = 0; t < nt; ++t)
      if (tp[t] >= 0)
        for (const std::int32_t d : nodes_of(t)) ++at[static_cast<std::size_t>(d) + 1];
    for (std::size_t d = 0; d < nd; ++d) at[d + 1] += at[d];
    std::vector<std::int32_t> parts_at(at[nd]);
    std::vector<std::uint32_t> count(nd, 0);
    for (std::size_t t = 0; t < nt; ++t) {
      if (tp[t] < 0) continue;
      for (const std::int32_t d : nodes_of(t)) {
        const auto n = static_cast<std::size_t>(d);
        parts_at[at[n] + count[n]++] = tp[t];
        if (tp[t] == me_) own_node[n] = 1;
      }
    }
    for (std::size_t d = 0; d < nd; ++d) {
      const auto first = parts_at.begin() + at[d], last = first + count[d];
      std::sort(first, last);
      count[d] = static_cast<std::uint32_t>(std::unique(first, last) - first);
    }
    const auto around = [&](std::size_t d) {
      return std::make_pair(parts_at.data() + at[d], parts_at.data() + at[d] + count[d]);
    };
    owner_.assign(nd, -1);
    gid_.assign(nd, -1);
    std::int64_t owned = 0;
    for (std::size_t d = 0; d < nd; ++d) {
      if (!own_node[d]) continue;
      owner_[d] = *around(d).first;  // the lowest
      if (owner_[d] == me_) gid_[d] = owned++;
    }
    const std::vector<std::uint64_t> counts = detail::all_gather({static_cast<std::uint64_t>(owned)});
    first_ = 0;
    total_ = 0;
    for (int q = 0; q < parts_; ++q) {
      if (q < me_) first_ += static_cast<std::int64_t>(counts[static_cast<std::size_t>(q)]);
      total_ += static_cast<std::int64_t>(counts[static_cast<std::size_t>(q)]);
    }
    owned_ = owned;
    dof_of_name_.resize(nd);
    for (std::size_t d = 0; d < nd; ++d) {
      dof_of_name_[d] = {dof_name_[d], static_cast<std::int32_t>(d)};
      if (gid_[d] >= 0) gid_[d] += first_;
    }
    // By name; a name met twice keeps its last node first, as a map assigned in node order would.
    std::sort(dof_of_name_.begin(), dof_of_name_.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second > b.second;
    });
    dof_of_name_.shrink_to_fit();
    // The other nodes of the own triangles: their numbers from their owners.
    std::vector<std::vector<std::uint64_t>> ask(static_cast<std::size_t>(parts_));
    std::vector<std::vector<std::int32_t>> asked(static_cast<std::size_t>(parts_));
    for (std::size_t d = 0; d < nd; ++d)
      if (own_node[d] && owner_[d] != me_) {
        ask[static_cast<std::size_t>(owner_[d])].push_back(dof_name_[d]);
        asked[static_cast<std::size_t>(owner_[d])].push_back(static_cast<std::int32_t>(d));
      }
    const auto questions = detail::all_to_all(ask);
    std::vector<std::vector<std::uint64_t>> answers(static_cast<std::size_t>(parts_));
    for (int q = 0; q < parts_; ++q)
      for (const std::uint64_t n : questions[static_cast<std::size_t>(q)])
        answers[static_cast<std::size_t>(q)].push_back(static_cast<std::uint64_t>(gid_.at(static_cast<std::size_t>(dof(n)))));
    const auto got = detail::all_to_all(answers);
    for (int q = 0; q < parts_; ++q)
      for (std::size_t i = 0; i < asked[static_cast<std::size_t>(q)].size(); ++i)
        gid_[static_cast<std::size_t>(asked[static_cast<std::size_t>(q)][i])] =
            static_cast<std::int64_t>(got[static_cast<std::size_t>(q)].at(i));
    // Whose first ghost layer each own triangle is in: they receive its nodes' values.
    push_.assign(static_cast<std::size_t>(parts_), {});
    std::vector<std::vector<char>> pushed(static_cast<std::size_t>(parts_));
    for (std::size_t t = 0; t < nt; ++t) {
      if (tp[t] != me_) continue;
      std::vector<std::int32_t> to;
      for (const std::int32_t c : fe.triangles[t])
        for (auto [q, end] = around(static_cast<std::size_t>(c)); q != end; ++q)
          if (*q != me_) add_unique(to, *q);
      for (const std::int32_t q : to) {
        auto& mark = pushed[static_cast<std::size_t>(q)];
        if (mark.empty()) mark.assign(nd, 0);
        for (const std::int32_t d : nodes_of(t))
          if (!mark[static_cast<std::size_t>(d)]) {
            mark[static_cast<std::size_t>(d)] = 1;
            push_[static_cast<std::size_t>(q)].push_back(d);
          }
      }
    }
    return tp;
  }

  // ---- the system: own triangles' entries to the rows' owners; values back and around ----
  // a is released once read (SharedLinearSolver): the AMG setup that follows is the peak.
  fem::LinearSolution solve(fem::SparseMatrix& a, const Eigen::VectorXd& b,
                            const std::vector<Eigen::Index>& row_of_dof, const Eigen::VectorXd* guess,
                            double tolerance) const {
    const Eigen::Index rows = a.rows();
    const std::size_t nd = row_of_dof.size();
    if (nd != gid_.size()) throw std::logic_error("distributed mesh: the system is not the numbered mesh's");
    std::vector<std::int32_t> dof_of_row(static_cast<std::size_t>(rows), -1);
    for (std::size_t d = 0; d < nd; ++d)
      if (row_of_dof[d] >= 0) dof_of_row[static_cast<std::size_t>(row_of_dof[d])] = static_cast<std::int32_t>(d);
    std::vector<detail::RowEntries> to(static_cast<std::size_t>(parts_));
    {  // (reserved: the entries are the largest transient of a solve)
      std::vector<std::size_t> entries(static_cast<std::size_t>(parts_), 0);
      for (Eigen::Index r = 0; r < a.outerSize(); ++r) {
        const std::int32_t d = dof_of_row[static_cast<std::size_t>(r)];
        if (d >= 0 && owner_[static_cast<std::size_t>(d)] >= 0)
          entries[static_cast<std::size_t>(owner_[static_cast<std::size_t>(d)])] +=
              static_cast<std::size_t>(a.outerIndexPtr()[r + 1] - a.outerIndexPtr()[r]) + 1;
      }
      for (int q = 0; q < parts_; ++q) {
        to[static_cast<std::size_t>(q)].index.reserve(2 * entries[static_cast<std::size_t>(q)]);
        to[static_cast<std::size_t>(q)].value.reserve(entries[static_cast<std::size_t>(q)]);
      }
    }
    for (Eigen::Index r = 0; r < a.outerSize(); ++r) {  // (symmetric: column r is row r)
      const auto d = static_cast<std::size_t>(dof_of_row[static_cast<std::size_t>(r)]);
      // (Stored zeros, which the assembly leaves where fixed values were, are no entries.)
      bool any = b[r] != 0.0;
      for (fem::SparseMatrix::InnerIterator it(a, r); it && !any; ++it) any = it.value() != 0.0;
      if (!any) continue;
      if (gid_[d] < 0) throw std::logic_error("distributed mesh: an entry at a node of no own triangle");
      detail::RowEntries& e = to[static_cast<std::size_t>(owner_[d])];
      for (fem::SparseMatrix::InnerIterator it(a, r); it; ++it)
        if (it.value() != 0.0) e.add(gid_[d], gid_[static_cast<std::size_t>(dof_of_row[static_cast<std::size_t>(it.index())])], it.value());
      if (b[r] != 0.0) e.add(gid_[d], -1, b[r]);
    }
    fem::SparseMatrix().swap(a);
    // The owner's fixed nodes (boundary values, the zero-mean problem's pinned vertex): rows
    // of the identity, their values set by the caller.
    Eigen::VectorXd start = Eigen::VectorXd::Zero(owned_);
    for (std::size_t d = 0; d < nd; ++d) {
      if (gid_[d] < 0 || owner_[d] != me_) continue;
      if (row_of_dof[d] < 0) {
        to[static_cast<std::size_t>(me_)].add(gid_[d], gid_[d], 1.0);
      } else if (guess != nullptr && guess->size() == rows) {
        start[gid_[d] - first_] = (*guess)[row_of_dof[d]];
      }
    }
    detail::OwnedRows solved = detail::solve_rows(to, first_, owned_, total_, &start, tolerance);
    // The values at the own triangles' nodes: from their owners.
    std::vector<double> value(nd, 0.0);
    std::vector<char> known(nd, 0);
    std::vector<std::vector<std::uint64_t>> ask(static_cast<std::size_t>(parts_));
    std::vector<std::vector<std::int32_t>> asked(static_cast<std::size_t>(parts_));
    for (std::size_t d = 0; d < nd; ++d) {
      if (gid_[d] < 0) continue;
      if (owner_[d] == me_) {
        value[d] = solved.x[gid_[d] - first_];
        known[d] = 1;
      } else {
        ask[static_cast<std::size_t>(owner_[d])].push_back(static_cast<std::uint64_t>(gid_[d]));
        asked[static_cast<std::size_t>(owner_[d])].push_back(static_cast<std::int32_t>(d));
      }
    }
    const auto questions = detail::all_to_all(ask);
    std::vector<std::vector<double>> answers(static_cast<std::size_t>(parts_));
    for (int q = 0; q < parts_; ++q)
      for (const std::uint64_t g : questions[static_cast<std::size_t>(q)])
        answers[static_cast<std::size_t>(q)].push_back(solved.x[static_cast<std::int64_t>(g) - first_]);
    const auto got = detail::all_to_all(answers);
    for (int q = 0; q < parts_; ++q)
      for (std::size_t i = 0; i < asked[static_cast<std::size_t>(q)].size(); ++i) {
        const auto d = static_cast<std::size_t>(asked[static_cast<std::size_t>(q)][i]);
        value[d] = got[static_cast<std::size_t>(q)].at(i);
        known[d] = 1;
      }
    // ... and at the first ghost layer's nodes: from the processes owning those triangles.
    std::vector<std::vector<std::uint64_t>> names_to(static_cast<std::size_t>(parts_));
    std::vector<std::vector<double>> values_to(static_cast<std::size_t>(parts_));
    for (int q = 0; q < parts_; ++q)
      for (const std::int32_t d : push_[static_cast<std::size_t>(q)]) {
        names_to[static_cast<std::size_t>(q)].push_back(dof_name_[static_cast<std::size_t>(d)]);
        values_to[static_cast<std::size_t>(q)].push_back(value[static_cast<std::size_t>(d)]);
      }
    const auto names_from = detail::all_to_all(names_to);
    const auto values_from = detail::all_to_all(values_to);
    for (int q = 0; q < parts_; ++q)
      for (std::size_t i = 0; i < names_from[static_cast<std::size_t>(q)].size(); ++i) {
        const std::int32_t d = dof(names_from[static_cast<std::size_t>(q)][i]);
        if (d < 0 || known[static_cast<std::size_t>(d)]) continue;
        value[static_cast<std::size_t>(d)] = values_from[static_cast<std::size_t>(q)][i];
        known[static_cast<std::size_t>(d)] = 1;
      }
    fem::LinearSolution out;
    out.x = Eigen::VectorXd::Zero(rows);
    for (std::size_t d = 0; d < nd; ++d)
      if (row_of_dof[d] >= 0) out.x[row_of_dof[d]] = value[d];
    out.iterations = solved.iterations;
    out.relative_residual = solved.relative_residual;
    return out;
  }

 private:
  std::int32_t dof(std::uint64_t name) const {
    const auto it = std::lower_bound(dof_of_name_.begin(), dof_of_name_.end(), name,
                                     [](const auto& entry, std::uint64_t n) { return entry.first < n; });
    return it == dof_of_name_.end() || it->first != name ? -1 : it->second;
  }

  // Whether the parts decided last are still balanced enough to keep for this cycle: the
  // largest part's triangles at most 10% above the mean, or at most 2% above the imbalance
  // that METIS left when it made them (a step's first solve follows a solve of the same
  // mesh). Only where the units are the floor's cells (runs that coarsen): elsewhere they are
  // divided by each cycle's refinement. Deciding the parts anew costs passes over the whole
  // view (the units placed and agreed, METIS, the migration): with three solves per step,
  // about a third of a distributed moving peak's own work, where 10% more triangles on the
  // largest part costs its part-sized stages (assembly, solve, estimate) a tenth more.
  // (part: parts_of(view).)
  bool parts_still_balanced(const RgbMesh& view, const std::vector<std::int32_t>& part) const {
    if (!std::isinf(share_)) return false;
    std::uint64_t own = 0;
    for (const TriangleHandle t : view.triangles()) own += part[static_cast<std::size_t>(t.idx)] == me_ ? 1 : 0;
    const std::vector<std::uint64_t> counts = detail::all_gather({own});
    std::uint64_t total = 0, largest = 0;
    for (const std::uint64_t c : counts) {
      total += c;
      largest = std::max(largest, c);
    }
    if (total == 0) return false;
    const double imbalance =
        static_cast<double>(largest) * static_cast<double>(counts.size()) / static_cast<double>(total);
    return imbalance <= std::max(1.1, 1.02 * partitioned_imbalance_);
  }

  // METIS numbers the parts it makes afresh each time: on two processes it may give the
  // moving peak's parts the other way round, and then nearly every triangle migrates. The new
  // parts are renumbered so that each keeps as many of a process's triangles as it can (the
  // largest overlaps first), the same on every process. Each process hands the others only the
  // overlaps of its own triangles (a few new parts each), not a P x P table.
  // `counted`: this process's triangles before; `part`: their new parts. Returns whether any
  // part was renumbered (unit_part_ then is).
  bool relabel_to_stay(const std::vector<char>& counted, const std::vector<std::int32_t>& part) {
    const auto p = static_cast<std::size_t>(parts_);
    std::vector<std::uint64_t> mine(p, 0);  // per new part: this process's triangles in it
    for (std::size_t t = 0; t < counted.size(); ++t)
      if (counted[t] && part[t] >= 0) ++mine[static_cast<std::size_t>(part[t])];
    std::vector<std::uint64_t> sent;  // (count, new part, old part: this process)
    for (std::size_t q = 0; q < p; ++q)
      if (mine[q] > 0) sent.insert(sent.end(), {mine[q], q, static_cast<std::uint64_t>(me_)});
    const std::vector<std::uint64_t> all = detail::all_gather(sent);
    std::vector<std::array<std::uint64_t, 3>> overlap;
    for (std::size_t i = 0; i + 2 < all.size(); i += 3) overlap.push_back({all[i], all[i + 1], all[i + 2]});
    // The largest overlaps first; ties by new part, then old.
    std::sort(overlap.begin(), overlap.end(), [](const auto& x, const auto& y) {
      return x[0] != y[0] ? x[0] > y[0] : x[1] != y[1] ? x[1] < y[1] : x[2] < y[2];
    });
    std::vector<std::int32_t> label(p, -1);
    std::vector<char> taken(p, 0);
    for (const auto& [count, fresh, old] : overlap) {
      if (label[fresh] >= 0 || taken[old]) continue;
      label[fresh] = static_cast<std::int32_t>(old);
      taken[old] = 1;
    }
    // New parts that overlap no free old one take the old numbers left, in order.
    std::size_t next_old = 0;
    for (std::size_t fresh = 0; fresh < p; ++fresh) {
      if (label[fresh] >= 0) continue;
      while (taken[next_old]) ++next_old;
      label[fresh] = static_cast<std::int32_t>(next_old);
      taken[next_old] = 1;
    }
    bool changed = false;
    for (std::size_t q = 0; q < p; ++q) changed = changed || label[q] != static_cast<std::int32_t>(q);
    if (!changed) return false;
    for (std::int32_t& q : unit_part_) q = label[static_cast<std::size_t>(q)];
    return true;
  }

  // Each triangle's part (per slot; -1 where the view is coarser than the whole mesh).
  std::vector<std::int32_t> parts_of(const RgbMesh& view) const {
    std::vector<std::int32_t> unit = locate_units(view, floor_, units_, cache_.get());
    for (std::int32_t& u : unit) u = u >= 0 ? unit_part_[static_cast<std::size_t>(u)] : -1;
    return unit;
  }

  // Flags the triangles of this process's part, per slot (of the parts per slot, or of the
  // view).
  std::vector<char> own_of(const std::vector<std::int32_t>& part) const {
    std::vector<char> own(part.size(), 0);
    for (std::size_t t = 0; t < part.size(); ++t) own[t] = part[t] == me_;
    return own;
  }
  std::vector<char> own_triangles(const RgbMesh& view) const { return own_of(parts_of(view)); }

  // Sends each process the vertices of this process's own triangles (`counted`) that its new
  // part (`part`, per triangle slot) or ghost layers hold, with their ancestors above the
  // floor; inserts what it receives.
  void migrate(RgbMesh& view, const std::vector<char>& counted, const std::vector<std::int32_t>& part,
               bool away_first = false) {
    // A triangle of this process goes to q when q's part is within two rings of one of its
    // corners: q's triangles' corners (one ring), then the corners of every triangle touching
    // them (two rings). Three passes of flags per other part in the view (its neighbours, a
    // few), where lists of parts per vertex in hash maps cost 2.9 s when a repartition moved
    // half of a 1.5-million-triangle view (the moving peak at 730,000 unknowns).
    const auto slots = static_cast<std::size_t>(view.vertex_slots());
    std::vector<char> other_part(static_cast<std::size_t>(parts_), 0);
    for (const TriangleHandle t : view.triangles()) {
      const std::int32_t q = part[static_cast<std::size_t>(t.idx)];
      if (q >= 0 && q != me_) other_part[static_cast<std::size_t>(q)] = 1;
    }
    std::vector<std::vector<char>> sending(static_cast<std::size_t>(parts_));
    for (std::int32_t q = 0; q < parts_; ++q) {
      if (!other_part[static_cast<std::size_t>(q)]) continue;
      const std::vector<char> near = corners_and_layers(view, part, q, 1);  // within two rings of q's part
      auto& s = sending[static_cast<std::size_t>(q)];
      for (const TriangleHandle t : view.triangles()) {
        if (!counted[static_cast<std::size_t>(t.idx)]) continue;
        const auto c = view.triangle_vertices(t);
        if (!near[static_cast<std::size_t>(c[0].idx)] && !near[static_cast<std::size_t>(c[1].idx)] &&
            !near[static_cast<std::size_t>(c[2].idx)])
          continue;
        if (s.empty()) s.assign(slots, 0);
        for (const VertexHandle v : c) s[static_cast<std::size_t>(v.idx)] = 1;
      }
    }
    const std::vector<VertexName> name = vertex_names(view);
    std::vector<std::vector<std::uint64_t>> to(static_cast<std::size_t>(parts_));
    for (int q = 0; q < parts_; ++q) {
      auto& s = sending[static_cast<std::size_t>(q)];
      if (s.empty()) continue;
      // With their ancestors above the base mesh (every view has the base's vertices; the
      // floor's only near its part).
      std::vector<VertexHandle> stack;
      for (const VertexHandle v : view.vertices())
        if (s[static_cast<std::size_t>(v.idx)]) stack.push_back(v);
      while (!stack.empty()) {
        const VertexHandle v = stack.back();
        stack.pop_back();
        if (view.level(v) <= kViewFloor) continue;
        const auto& p = view.parents(v);
        append(to[static_cast<std::size_t>(q)],
               {name[static_cast<std::size_t>(v.idx)], name[static_cast<std::size_t>(p[0].idx)],
                name[static_cast<std::size_t>(p[1].idx)], static_cast<std::uint64_t>(view.level(v))});
        for (const VertexHandle u : p)
          if (!s[static_cast<std::size_t>(u.idx)]) {
            s[static_cast<std::size_t>(u.idx)] = 1;
            stack.push_back(u);
          }
      }
    }
    if (away_first) {
      // Away from the new part before receiving, so that what arrives takes the slots that the
      // old part's vertices leave: the view's arrays then grow to its largest size, not to its
      // old and new parts together (which kept 505,000 vertex slots for 282,000 vertices).
      coarsen_away(view, own_of(part), kViewFloor, kGhostLayers);
    }
    const auto from = detail::all_to_all(to);
    std::vector<Travelling> items;
    for (int q = 0; q < parts_; ++q)
      if (q != me_)
        for (const Travelling& t : unpack(from[static_cast<std::size_t>(q)])) items.push_back(t);
    std::unordered_set<VertexName> handed;
    for (const Travelling& t : items) handed.insert(t.name);
    Names names(view);
    const std::vector<Travelling> left = insert(view, names, std::move(items));
    if (!left.empty())
      throw std::logic_error("distributed mesh: " + std::to_string(left.size()) +
                             " vertices handed over could not be inserted (the first of level " +
                             std::to_string(left.front().level) + ")");
    // Where this view was coarser than the whole mesh around a vertex's parents, split_edge
    // made forced splits the whole mesh has not made (it reached that vertex otherwise): out
    // again, finest first, as far as they can go.
    std::vector<VertexHandle> forced;
    for (const VertexHandle v : names.inserted)
      if (view.alive(v) && !handed.count(names.of(v))) forced.push_back(v);
    remove_finest_first(view, std::move(forced));
  }

  int floor_, parts_, me_;
  double share_;
  double compact_below_;  // AdaptOptions::compact_below
  // Coarsening rounds that removed something (each one exchanges the removals and makes the
  // ghost layers exact again), and the counts last reported (rounds_since_last).
  std::uint64_t rounds_ = 0, rounds_reported_ = 0, exchanges_reported_ = 0;
  std::shared_ptr<FloorCache> cache_ = make_floor_cache();
  bool whole_ = true;  // every process holds the whole mesh (before the first cycle)
  double partitioned_imbalance_ = 1;  // the parts' imbalance when METIS made them
  Units units_;
  std::vector<std::int32_t> unit_part_;
  NameSet known_;   // its vertices
  NameSet region_;  // the part's and its ghost layers' vertices (and those between them)
  std::vector<std::int32_t> neighbours_;    // the processes owning some of its ghost layers
  // The numbered finite-element mesh.
  std::vector<VertexName> dof_name_;
  std::vector<std::pair<VertexName, std::int32_t>> dof_of_name_;  // sorted by name
  std::vector<std::int64_t> gid_;
  std::vector<std::int32_t> owner_;
  std::int64_t first_ = 0, owned_ = 0, total_ = 0;
  std::vector<std::vector<std::int32_t>> push_;
};

}  // namespace

bool mesh_can_be_distributed(const adapt::AdaptOptions& options) { return !options.control.resumable; }

void distribute_mesh(adapt::AdaptOptions& options) {
  const int parts = processes();
  if (parts <= 1) return;
  if (!mesh_can_be_distributed(options))
    throw std::invalid_argument(
        "distribute_mesh: a run with resumable files keeps the whole mesh (distribute)");
  // A run that coarsens takes the floor's cells as its units: a coarsened triangle stays in
  // one of them, where a divided cell's units could each hold part of it.
  const bool coarsens = options.coarsen_below > 0;
  auto state = std::make_shared<DistributedMesh>(options.min_level, parts, rank(),
                                                 coarsens ? std::numeric_limits<double>::infinity() : 0.1,
                                                 options.compact_below);
  options.distribution.distributed_mesh = true;
  options.distribution.prepare_mesh = [state](RgbMesh& view) { state->prepare(view); };
  options.distribution.after_adaptation = [state](RgbMesh& view) { state->reconcile(view); };
  options.distribution.coarsen_mesh = [state](RgbMesh& view, const LodCriterion& c) {
    return state->coarsen(view, c);
  };
  options.distribution.partition = [state](const RgbMesh& view, const fem::SurfaceMesh& fe) {
    return state->number(view, fe);
  };
  options.distribution.share.process = rank();
  options.distribution.share.sum = sum;
  // Each process keeps its own triangles' indicators: nothing to gather.
  options.distribution.share.gather = [](double*, std::size_t, const std::vector<std::int32_t>&) {};
  options.distribution.bytes_sent = bytes_sent_since_last;
  options.distribution.rounds = [state] { return state->rounds_since_last(); };
  options.solve.shared_solver =
      [state](fem::SparseMatrix& a, const Eigen::VectorXd& b, const std::vector<std::int32_t>&,
              const std::vector<Eigen::Index>& row_of_dof, const Eigen::VectorXd* guess,
              double tolerance) { return state->solve(a, b, row_of_dof, guess, tolerance); };
}

}  // namespace rgbmesh::parallel
