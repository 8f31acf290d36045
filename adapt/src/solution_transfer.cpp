#include "rgbmesh/adapt/solution_transfer.hpp"

#include <algorithm>
#include <utility>

namespace rgbmesh::adapt {

namespace {

// The six P2 basis functions at barycentric coordinates l (corners, then edges 0-1, 1-2, 2-0).
double quadratic_at(const std::array<double, 6>& values, const std::array<double, 3>& l) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    s += values[k] * l[k] * (2 * l[k] - 1);
    s += values[3 + k] * 4 * l[k] * l[(k + 1) % 3];
  }
  return s;
}

}  // namespace

SolutionTransfer::SolutionTransfer(RgbMesh& mesh) : mesh_(mesh) { observe(); }

SolutionTransfer::~SolutionTransfer() {
  mesh_.remove_observer(insertion_id_);
  mesh_.remove_observer(removal_id_);
  mesh_.remove_observer(renumbering_id_);
}

std::uint64_t SolutionTransfer::key(VertexHandle a, VertexHandle b) {
  auto x = static_cast<std::uint32_t>(a.idx), y = static_cast<std::uint32_t>(b.idx);
  if (x > y) std::swap(x, y);
  return (static_cast<std::uint64_t>(x) << 32) | y;
}

const double* SolutionTransfer::edge_value(VertexHandle a, VertexHandle b) const {
  const auto it = edges_.find(key(a, b));
  if (it == edges_.end()) return nullptr;
  const auto low = static_cast<std::size_t>(std::min(a.idx, b.idx)), high = static_cast<std::size_t>(std::max(a.idx, b.idx));
  if (it->second.born_low != born_[low] || it->second.born_high != born_[high]) return nullptr;
  return &it->second.value;
}

void SolutionTransfer::set_edge_value(VertexHandle a, VertexHandle b, double value) {
  const auto low = static_cast<std::size_t>(std::min(a.idx, b.idx)), high = static_cast<std::size_t>(std::max(a.idx, b.idx));
  edges_[key(a, b)] = EdgeValue{value, born_[low], born_[high]};
}

void SolutionTransfer::store(const fem::SurfaceMesh& fe, const Eigen::VectorXd& u) {
  grow();
  for (std::size_t i = 0; i < fe.vertex.size(); ++i) values_[fe.vertex[i].idx] = u[static_cast<Eigen::Index>(i)];
  quadratic_ = fe.order == 2;
  edges_.clear();
  old_.clear();
  old_star_.clear();
  std::fill(locations_.begin(), locations_.end(), Location{});
  if (quadratic_) {
    const std::size_t nt = fe.triangles.size();
    old_.resize(nt);
    old_star_.resize(values_.size());
    edges_.reserve(nt * 2);
    std::unordered_map<std::uint64_t, std::pair<std::int32_t, int>> first;  // edge -> (element, local edge)
    first.reserve(nt * 2);
    for (std::size_t t = 0; t < nt; ++t) {
      OldElement& e = old_[t];
      const auto ti = static_cast<std::int32_t>(t);
      for (int k = 0; k < 3; ++k) {
        e.corners[k] = fe.vertex[fe.triangles[t][k]];
        e.values[k] = u[fe.triangles[t][k]];
        e.values[3 + k] = u[fe.edge_nodes[t][k]];
        e.across[k] = -1;
        old_star_[e.corners[k].idx].push_back(ti);
        locations_[e.corners[k].idx].element = Location::kOldVertex;
      }
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t edge = key(e.corners[k], e.corners[(k + 1) % 3]);
        set_edge_value(e.corners[k], e.corners[(k + 1) % 3], e.values[3 + k]);
        const auto [it, inserted] = first.try_emplace(edge, ti, k);
        if (!inserted) {
          e.across[k] = it->second.first;
          old_[static_cast<std::size_t>(it->second.first)].across[it->second.second] = ti;
        }
      }
    }
  }
  has_values_ = true;
}

std::optional<std::array<double, 3>> SolutionTransfer::coordinates_in(VertexHandle x, std::int32_t e) const {
  if (x.idx < 0 || static_cast<std::size_t>(x.idx) >= locations_.size()) return std::nullopt;
  const Location& l = locations_[x.idx];
  const OldElement& element = old_[static_cast<std::size_t>(e)];
  if (l.element == Location::kOldVertex) {
    for (int k = 0; k < 3; ++k) {
      if (element.corners[k] == x) {
        std::array<double, 3> corner{};
        corner[k] = 1;
        return corner;
      }
    }
    return std::nullopt;
  }
  if (l.element == e) return l.lambda;
  if (l.element < 0) return std::nullopt;
  // On edge k of its element (the opposite corner's coordinate 0), x lies in the element across.
  const OldElement& home = old_[static_cast<std::size_t>(l.element)];
  for (int k = 0; k < 3; ++k) {
    if (l.lambda[(k + 2) % 3] != 0 || home.across[k] != e) continue;
    std::array<double, 3> there{};
    for (int side : {k, (k + 1) % 3}) {
      for (int j = 0; j < 3; ++j)
        if (element.corners[j] == home.corners[side]) there[j] = l.lambda[side];
    }
    return there;
  }
  return std::nullopt;
}

std::optional<double> SolutionTransfer::at_midpoint(VertexHandle p, VertexHandle q, Location* where) const {
  if (p.idx < 0 || static_cast<std::size_t>(p.idx) >= locations_.size()) return std::nullopt;
  const Location& l = locations_[p.idx];
  // The old elements p lies in: its old star, or its element and the neighbours across the
  // edges it lies on.
  std::array<std::int32_t, 4> near{-1, -1, -1, -1};
  const std::vector<std::int32_t>* star = nullptr;
  if (l.element == Location::kOldVertex) {
    star = &old_star_[p.idx];
  } else if (l.element >= 0) {
    near[0] = l.element;
    for (int k = 0; k < 3; ++k)
      if (l.lambda[(k + 2) % 3] == 0) near[1 + k] = old_[static_cast<std::size_t>(l.element)].across[k];
  }
  const auto try_element = [&](std::int32_t e) -> std::optional<double> {
    if (e < 0) return std::nullopt;
    const auto lq = coordinates_in(q, e);
    if (!lq) return std::nullopt;
    const auto lp = coordinates_in(p, e);
    if (!lp) return std::nullopt;
    std::array<double, 3> mid{};
    for (int k = 0; k < 3; ++k) mid[k] = 0.5 * ((*lp)[k] + (*lq)[k]);
    if (where) *where = Location{e, mid};
    return quadratic_at(old_[static_cast<std::size_t>(e)].values, mid);
  };
  if (star) {
    for (const std::int32_t e : *star)
      if (const auto value = try_element(e)) return value;
  } else {
    for (const std::int32_t e : near)
      if (const auto value = try_element(e)) return value;
  }
  return std::nullopt;
}

Eigen::VectorXd SolutionTransfer::on(const fem::SurfaceMesh& fe) const {
  if (!has_values_) return {};
  Eigen::VectorXd u(static_cast<Eigen::Index>(fe.num_dofs()));
  u.head(static_cast<Eigen::Index>(fe.vertex.size())) = at(fe.vertex);
  for (std::size_t t = 0; t < fe.edge_nodes.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = fe.triangles[t][k], b = fe.triangles[t][(k + 1) % 3];
      const VertexHandle va = fe.vertex[a], vb = fe.vertex[b];
      double value = 0.5 * (u[a] + u[b]);
      if (quadratic_) {
        if (const double* known = edge_value(va, vb))
          value = *known;
        else if (const auto mid = at_midpoint(va, vb))
          value = *mid;
      }
      u[fe.edge_nodes[t][k]] = value;
    }
  }
  return u;
}

Eigen::VectorXd SolutionTransfer::at(const std::vector<VertexHandle>& vertices) const {
  if (!has_values_) return {};
  Eigen::VectorXd u(static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) u[static_cast<Eigen::Index>(i)] = values_[vertices[i].idx];
  return u;
}

void SolutionTransfer::observe() {
  insertion_id_ = mesh_.add_insertion_observer(
      [this](VertexHandle v, VertexHandle a, VertexHandle b) { inserted(v, a, b); });
  removal_id_ = mesh_.add_removal_observer([this](VertexHandle v) { removing(v); });
  renumbering_id_ = mesh_.add_renumbering_observer([this](const RgbMesh::Renumbering& map) { renumbered(map); });
}

void SolutionTransfer::grow() {
  const auto slots = static_cast<std::size_t>(mesh_.vertex_slots());
  if (values_.size() < slots) values_.resize(slots, 0.0);
  if (born_.size() < slots) born_.resize(slots, 0);
  if (locations_.size() < slots) locations_.resize(slots);
  if (quadratic_ && old_star_.size() < slots) old_star_.resize(slots);
}

void SolutionTransfer::inserted(VertexHandle v, VertexHandle a, VertexHandle b) {
  grow();
  ++born_[v.idx];
  const double mean = 0.5 * (values_[a.idx] + values_[b.idx]);
  if (!quadratic_) {
    values_[v.idx] = mean;
    return;
  }
  Location where;
  const auto mid = at_midpoint(a, b, &where);
  const double* known = edge_value(a, b);
  values_[v.idx] = known ? *known : mid ? *mid : mean;
  locations_[v.idx] = mid ? where : Location{};
  old_star_[v.idx].clear();
}

void SolutionTransfer::removing(VertexHandle v) {
  if (!quadratic_) return;
  // The merged edge's node is where v was: it takes v's value. v's edges and place go (the
  // slot may be reused by a vertex elsewhere).
  const auto [a, b] = mesh_.parents(v);
  for (const VertexHandle c : mesh_.star(v).neighbors) edges_.erase(key(v, c));
  if (a.valid() && b.valid()) set_edge_value(a, b, values_[v.idx]);
  locations_[v.idx] = Location{};
  old_star_[v.idx].clear();
}

void SolutionTransfer::renumbered(const RgbMesh::Renumbering& map) {
  // Per-slot data moves with its vertex (a free slot's goes); old elements keep their corners,
  // a removed one named by a number no slot has (-2 - its old slot), so that corners still
  // compare equal exactly when they are the same vertex.
  const auto keep = [&](auto& by_slot) {
    std::size_t live = 0;
    for (std::size_t i = 0; i < map.vertex.size() && i < by_slot.size(); ++i) {
      if (map.vertex[i] < 0) continue;
      ++live;
      // (never upwards; not onto itself: a vector moved onto itself is left empty)
      if (static_cast<std::size_t>(map.vertex[i]) != i) by_slot[static_cast<std::size_t>(map.vertex[i])] = std::move(by_slot[i]);
    }
    by_slot.resize(std::min(by_slot.size(), live));
    by_slot.shrink_to_fit();
  };
  keep(values_);
  keep(born_);
  keep(locations_);
  keep(old_star_);
  const auto moved = [&](VertexHandle v) {
    if (v.idx < 0) return v;
    const std::int32_t to = map.vertex[static_cast<std::size_t>(v.idx)];
    return VertexHandle(to >= 0 ? to : -2 - v.idx);
  };
  for (OldElement& e : old_)
    for (VertexHandle& corner : e.corners) corner = moved(corner);
  std::unordered_map<std::uint64_t, EdgeValue> edges;
  edges.reserve(edges_.size());
  for (const auto& [k, ev] : edges_) {
    const auto low = static_cast<std::size_t>(k >> 32), high = static_cast<std::size_t>(k & 0xffffffffu);
    const std::int32_t a = map.vertex[low], b = map.vertex[high];
    if (a < 0 || b < 0) continue;  // an end was removed: the entry can never be read again
    edges.emplace(key(VertexHandle(a), VertexHandle(b)), ev);  // (births moved with the slots)
  }
  edges_.swap(edges);
}

}  // namespace rgbmesh::adapt
