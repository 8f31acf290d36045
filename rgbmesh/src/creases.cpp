// Sharp features in the core (creases.hpp): the sharpness of the rails' pieces level by level,
// and a vertex's control points through the levels where its rules change.

#include "creases.hpp"

#include <algorithm>
#include <cassert>
#include <stdexcept>

#include "rgbmesh/mesh.hpp"  // kMaxLevel

namespace rgbmesh {

const char* to_string(CreaseMethod method) { return method == CreaseMethod::chaikin ? "chaikin" : "uniform"; }

const char* to_string(VertexRule rule) {
  switch (rule) {
    case VertexRule::smooth: return "smooth";
    case VertexRule::dart: return "dart";
    case VertexRule::crease: return "crease";
    case VertexRule::corner: return "corner";
  }
  return "?";
}

bool SharpFeatures::empty() const {
  const auto sharp_edge = [](const SharpEdge& e) { return e.sharpness > 0.0f; };
  const auto sharp_vertex = [](const SharpVertex& v) { return v.sharpness > 0.0f; };
  return std::none_of(edges.begin(), edges.end(), sharp_edge) &&
         std::none_of(vertices.begin(), vertices.end(), sharp_vertex);
}

bool SharpFeatures::operator==(const SharpFeatures& o) const {
  if (method != o.method || edges.size() != o.edges.size() || vertices.size() != o.vertices.size()) return false;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const SharpEdge &x = edges[i], &y = o.edges[i];
    if (x.a != y.a || x.b != y.b || x.sharpness != y.sharpness) return false;
  }
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i].v != o.vertices[i].v || vertices[i].sharpness != o.vertices[i].sharpness) return false;
  }
  return true;
}

namespace detail {

namespace {

std::uint64_t ends_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Beyond this many levels below a rail's own, a piece index no longer fits: by then every
// semi-sharp value has decayed (at most 11 levels), so the index is not looked at.
constexpr int kIndexedLevels = 48;

}  // namespace

CreaseTable::CreaseTable(const SharpFeatures& features, std::size_t base_vertices)
    : features_(features), method_(features.method), rails_at_(base_vertices) {
  for (const SharpEdge& e : features.edges) {
    const auto r = static_cast<std::int32_t>(rails_.size());
    rails_.push_back({std::min(e.a, e.b), std::max(e.a, e.b), std::min(e.sharpness, kInfiniteSharpness)});
    by_ends_.emplace(ends_key(e.a, e.b), r);
    rails_at_[static_cast<std::size_t>(e.a)].push_back(r);
    rails_at_[static_cast<std::size_t>(e.b)].push_back(r);
  }
  if (!features.vertices.empty()) {
    vertex_sharpness_.assign(base_vertices, 0.0f);
    for (const SharpVertex& v : features.vertices)
      vertex_sharpness_[static_cast<std::size_t>(v.v)] = std::min(v.sharpness, kInfiniteSharpness);
  }
  if (method_ == CreaseMethod::chaikin) build_chaikin();
}

std::int32_t CreaseTable::rail_of(std::int32_t a, std::int32_t b) const {
  const auto it = by_ends_.find(ends_key(a, b));
  return it == by_ends_.end() ? -1 : it->second;
}

const std::vector<std::int32_t>& CreaseTable::rails_at(std::int32_t v) const {
  return rails_at_[static_cast<std::size_t>(v)];
}

float CreaseTable::segment(std::int32_t r, int level, std::uint64_t index) const {
  const float s = rails_[static_cast<std::size_t>(r)].sharpness;
  if (s >= kInfiniteSharpness) return kInfiniteSharpness;
  if (method_ == CreaseMethod::uniform) {
    float x = s;
    for (int k = 0; k < level && x > 0.0f; ++k) x = loop::decrement_sharpness(x);
    return x;
  }
  const auto& levels = chaikin_[static_cast<std::size_t>(r)];
  if (static_cast<std::size_t>(level) >= levels.size()) return 0.0f;
  return levels[static_cast<std::size_t>(level)][index];
}

float CreaseTable::vertex(std::int32_t v, int level) const {
  if (vertex_sharpness_.empty()) return 0.0f;
  float x = vertex_sharpness_[static_cast<std::size_t>(v)];
  for (int k = 0; k < level && loop::is_semi_sharp(x); ++k) x = loop::decrement_sharpness(x);
  return x;
}

void CreaseTable::build_chaikin() {
  // All rails advance one level together: the pieces at a base vertex's end take their
  // children from every rail's end piece there at the same level (Chaikin's average).
  chaikin_.assign(rails_.size(), {});
  for (std::size_t r = 0; r < rails_.size(); ++r) {
    if (loop::is_semi_sharp(rails_[r].sharpness)) chaikin_[r].push_back({rails_[r].sharpness});
  }
  const auto end_piece = [this](std::int32_t q, std::int32_t v, std::size_t level) {
    const Rail& rail = rails_[static_cast<std::size_t>(q)];
    if (rail.sharpness >= kInfiniteSharpness) return kInfiniteSharpness;
    const auto& levels = chaikin_[static_cast<std::size_t>(q)];
    if (level >= levels.size()) return 0.0f;
    return v == rail.a ? levels[level].front() : levels[level].back();
  };
  std::vector<float> around;
  for (std::size_t level = 0;; ++level) {
    std::vector<std::pair<std::size_t, std::vector<float>>> next_levels;
    for (std::size_t r = 0; r < rails_.size(); ++r) {
      if (chaikin_[r].size() != level + 1) continue;  // smooth, infinite, or decayed already
      const std::vector<float>& now = chaikin_[r][level];
      const std::size_t n = now.size();
      std::vector<float> next(2 * n);
      bool sharp = false;
      const auto at_base_vertex = [&](std::int32_t v, float s) {
        around.clear();
        for (std::int32_t q : rails_at_[static_cast<std::size_t>(v)]) around.push_back(end_piece(q, v, level));
        return loop::child_sharpness(method_, s, around.data(), static_cast<int>(around.size()));
      };
      for (std::size_t i = 0; i < n; ++i) {
        const float s = now[i];
        float pair[2];
        if (i == 0) {
          next[2 * i] = at_base_vertex(rails_[r].a, s);
        } else {
          pair[0] = now[i - 1];
          pair[1] = s;
          next[2 * i] = loop::child_sharpness(method_, s, pair, 2);
        }
        if (i + 1 == n) {
          next[2 * i + 1] = at_base_vertex(rails_[r].b, s);
        } else {
          pair[0] = s;
          pair[1] = now[i + 1];
          next[2 * i + 1] = loop::child_sharpness(method_, s, pair, 2);
        }
        sharp = sharp || next[2 * i] > 0.0f || next[2 * i + 1] > 0.0f;
      }
      if (sharp) next_levels.emplace_back(r, std::move(next));
    }
    if (next_levels.empty()) break;
    for (auto& [r, next] : next_levels) chaikin_[r].push_back(std::move(next));
  }
}

namespace {

// The sharpness of the spokes and the vertex at any level, read off the table.
struct RingSharpness {
  const CreaseTable* table;
  const Ring& ring;

  // Spoke i's piece at `level` (the one at the vertex).
  float spoke(std::size_t i, int level) const {
    const Spoke& sp = ring.spokes[i];
    if (sp.boundary) return kInfiniteSharpness;
    if (sp.rail < 0 || table == nullptr) return 0.0f;
    return table->segment(sp.rail, level, piece(sp, level - ring.level, false));
  }
  // The child of spoke i's level-`level` piece at its far end, at level + 1.
  float far_child(std::size_t i, int level) const {
    const Spoke& sp = ring.spokes[i];
    if (sp.boundary) return kInfiniteSharpness;
    if (sp.rail < 0 || table == nullptr) return 0.0f;
    return table->segment(sp.rail, level + 1, piece(sp, level + 1 - ring.level, true));
  }
  float vertex(int level) const {
    return ring.base_vertex >= 0 && table != nullptr ? table->vertex(ring.base_vertex, level) : 0.0f;
  }
  static std::uint64_t piece(const Spoke& sp, int shift, bool far_end) {
    if (shift >= kIndexedLevels) return 0;  // decayed long ago: not looked at
    const std::uint64_t first = sp.piece << shift, last = ((sp.piece + 1) << shift) - 1;
    if (!far_end) return sp.vertex_first ? first : last;
    return sp.vertex_first ? first + 1 : last - 1;
  }
};

// A mask over the vertex and its spokes' far ends.
struct EvenMask {
  double self = 1.0;
  std::vector<double> spoke;
};

void assign_mask(VertexRule rule, const std::vector<float>& sharpness, bool open, EvenMask& mask) {
  const std::size_t n = sharpness.size();
  mask.spoke.assign(n, 0.0);
  switch (rule) {
    case VertexRule::smooth:
    case VertexRule::dart: {
      if (open) throw std::logic_error("rgbmesh: internal error: a smooth rule at a boundary vertex");
      const double a = loop::even_neighbor_weight(static_cast<int>(n));
      mask.self = 1.0 - static_cast<double>(n) * a;
      std::fill(mask.spoke.begin(), mask.spoke.end(), a);
      return;
    }
    case VertexRule::crease:
      mask.self = loop::kCreaseEvenSelf;
      for (std::size_t i = 0; i < n; ++i)
        if (sharpness[i] > 0.0f) mask.spoke[i] = loop::kCreaseEvenNeighbor;
      return;
    case VertexRule::corner:
      mask.self = 1.0;
      return;
  }
}

int sharp_count(const std::vector<float>& s) {
  return static_cast<int>(std::count_if(s.begin(), s.end(), [](float x) { return x > 0.0f; }));
}

bool settled_values(const std::vector<float>& spokes, float vertex) {
  const auto fixed = [](float x) { return x <= 0.0f || x >= kInfiniteSharpness; };
  return fixed(vertex) && std::all_of(spokes.begin(), spokes.end(), fixed);
}

}  // namespace

VertexRule ring_rule(const CreaseTable* table, const Ring& ring, int level) {
  const RingSharpness sharp{table, ring};
  int count = 0;
  for (std::size_t i = 0; i < ring.spokes.size(); ++i) count += sharp.spoke(i, level) > 0.0f;
  return loop::vertex_rule(sharp.vertex(level), count);
}

bool settled(const CreaseTable* table, const Ring& ring) {
  const RingSharpness sharp{table, ring};
  std::vector<float> s(ring.spokes.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = sharp.spoke(i, ring.level);
  const float v = sharp.vertex(ring.level);
  return settled_values(s, v) && loop::vertex_rule(v, sharp_count(s)) != VertexRule::dart;
}

Evolution evolve(const CreaseTable* table, const Ring& ring, int last_level) {
  const RingSharpness sharp{table, ring};
  const CreaseMethod method = table ? table->method() : CreaseMethod::uniform;
  const std::size_t n = ring.spokes.size();
  Vec3 centre = ring.centre;
  std::vector<Vec3> points(n), next(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = ring.spokes[i].point;
  std::vector<float> s(n), t(n);
  EvenMask parent, child;
  Evolution ev;
  ev.points.push_back(centre);
  // Past kMaxLevel a dart's ring is subdivided on (without recording) until it stops moving:
  // each level shrinks what is left by the subdominant eigenvalue (below 5/8).
  constexpr int kLimitLevels = 200;
  for (int level = ring.level;; ++level) {
    for (std::size_t i = 0; i < n; ++i) {
      s[i] = sharp.spoke(i, level);
      t[i] = sharp.spoke(i, level + 1);
    }
    const float vs = sharp.vertex(level), vt = sharp.vertex(level + 1);
    const VertexRule rule = loop::vertex_rule(vs, sharp_count(s));
    const bool fixed = settled_values(s, vs);
    if (fixed && rule != VertexRule::dart) {
      ev.rule = rule;
      if (rule == VertexRule::corner) {
        ev.g = 0.0;
        ev.limit = centre;
      } else if (rule == VertexRule::crease) {
        ev.g = loop::kBoundaryEigenvalue;
        Vec3 ends;
        for (std::size_t i = 0; i < n; ++i)
          if (s[i] > 0.0f) ends += points[i];
        ev.limit = loop::kBoundaryLimitSelf * centre + loop::kBoundaryLimitNeighbor * ends;
      } else {
        const int valence = static_cast<int>(n);
        const double b = loop::limit_neighbor_weight(valence);
        Vec3 sum;
        for (const Vec3& p : points) sum += p;
        ev.g = loop::subdominant_eigenvalue(valence);
        ev.limit = (1.0 - valence * b) * centre + b * sum;
      }
      return ev;
    }
    if (fixed && level >= last_level + kLimitLevels) {
      ev.rule = VertexRule::dart;
      ev.g = 0.0;  // unused: the points reach kMaxLevel
      ev.limit = centre;
      return ev;
    }
    if (level - ring.level > 2 * kIndexedLevels && !fixed)
      throw std::logic_error("rgbmesh: internal error: a semi-sharp feature does not decay");
    // The odd rule on every spoke gives the next ring (loop_rules.hpp, odd_mask).
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 ends = centre + points[i];
      if (s[i] <= 0.0f) {
        next[i] = loop::OddMask{}.end * ends + loop::OddMask{}.opposite * (points[(i + n - 1) % n] + points[(i + 1) % n]);
        continue;
      }
      const bool crease = t[i] > 0.0f && sharp.far_child(i, level) > 0.0f;
      const loop::OddMask mask = loop::odd_mask(s[i], crease);
      next[i] = mask.end * ends;
      if (mask.opposite != 0.0) next[i] += mask.opposite * (points[(i + n - 1) % n] + points[(i + 1) % n]);
    }
    // The even rule, blended where the rule changes (OpenSubdiv's ComputeVertexVertexMask).
    assign_mask(rule, s, ring.open, parent);
    if (rule == VertexRule::crease || rule == VertexRule::corner) {
      const VertexRule child_rule = loop::vertex_rule(vt, sharp_count(t));
      if (child_rule != rule) {
        assign_mask(child_rule, t, ring.open, child);
        const double w = loop::transition_weight(method, vs, vt, static_cast<int>(n), s.data(), t.data());
        const double c = 1.0 - w;
        parent.self = w * parent.self + c * child.self;
        for (std::size_t i = 0; i < n; ++i) parent.spoke[i] = w * parent.spoke[i] + c * child.spoke[i];
      }
    }
    Vec3 moved;
    for (std::size_t i = 0; i < n; ++i)
      if (parent.spoke[i] != 0.0) moved += parent.spoke[i] * points[i];
    moved += parent.self * centre;
    centre = moved;
    points.swap(next);
    if (level + 1 <= last_level) ev.points.push_back(centre);
  }
}

}  // namespace detail
}  // namespace rgbmesh
