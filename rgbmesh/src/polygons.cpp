// Polygon faces into triangles (polygons.hpp): a fan for planar convex polygons, ears cut in the
// polygon's plane for the others, refusing polygons that cross themselves.

#include "rgbmesh/polygons.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <tuple>

namespace rgbmesh {
namespace {

struct Point2 {
  double x = 0, y = 0;
};

// Twice the signed area of (a, b, c): positive when they turn left.
double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool same(const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }

// A uniform grid over the polygon's bounding box in its plane, about `items` cells, each listing
// the items (corners or edges) whose bounding boxes reach into it.
class Grid {
 public:
  Grid(const std::vector<Point2>& q, std::size_t items) {
    lo_ = hi_ = q.front();
    for (const Point2& p : q) {
      lo_.x = std::min(lo_.x, p.x), lo_.y = std::min(lo_.y, p.y);
      hi_.x = std::max(hi_.x, p.x), hi_.y = std::max(hi_.y, p.y);
    }
    side_ = static_cast<int>(std::clamp(std::ceil(std::sqrt(static_cast<double>(items))), 1.0, 1024.0));
    cells_.resize(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_));
  }

  // The cells a box covers, as [i0, i1] x [j0, j1].
  std::array<int, 4> range(Point2 a, Point2 b) const {
    return {cell(std::min(a.x, b.x), lo_.x, hi_.x), cell(std::max(a.x, b.x), lo_.x, hi_.x),
            cell(std::min(a.y, b.y), lo_.y, hi_.y), cell(std::max(a.y, b.y), lo_.y, hi_.y)};
  }
  void insert(const std::array<int, 4>& r, std::int32_t item) {
    for (int i = r[0]; i <= r[1]; ++i)
      for (int j = r[2]; j <= r[3]; ++j) at(i, j).push_back(item);
  }
  // The cells a segment passes through: column by column, the rows its stretch there reaches.
  void insert_segment(const Point2& a, const Point2& b, std::int32_t item) {
    const Point2& left = a.x <= b.x ? a : b;
    const Point2& right = a.x <= b.x ? b : a;
    const int i0 = cell(left.x, lo_.x, hi_.x), i1 = cell(right.x, lo_.x, hi_.x);
    const double width = (hi_.x - lo_.x) / side_;
    for (int i = i0; i <= i1; ++i) {
      // The segment's y at the column's sides (clamped to its ends).
      const double x0 = std::max(left.x, lo_.x + width * i), x1 = std::min(right.x, lo_.x + width * (i + 1));
      const double dx = right.x - left.x;
      const auto y_at = [&](double x) { return dx > 0 ? left.y + (right.y - left.y) * ((x - left.x) / dx) : left.y; };
      const double ya = i == i0 ? left.y : y_at(x0), yb = i == i1 ? right.y : y_at(x1);
      const int j0 = cell(std::min(ya, yb), lo_.y, hi_.y), j1 = cell(std::max(ya, yb), lo_.y, hi_.y);
      for (int j = std::max(0, j0 - 1); j <= std::min(side_ - 1, j1 + 1); ++j) at(i, j).push_back(item);
    }
  }

  // The cell of a point.
  std::size_t cell_of(const Point2& p) const {
    const std::array<int, 4> r = range(p, p);
    return index(r[0], r[2]);
  }
  std::vector<std::int32_t>& cell(std::size_t k) { return cells_[k]; }
  std::vector<std::int32_t>& at(int i, int j) { return cells_[index(i, j)]; }
  const std::vector<std::int32_t>& at(int i, int j) const { return cells_[index(i, j)]; }
  const std::vector<std::vector<std::int32_t>>& cells() const { return cells_; }

 private:
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(side_) + static_cast<std::size_t>(j);
  }
  int cell(double t, double lo, double hi) const {
    if (!(hi > lo)) return 0;
    const double f = (t - lo) / (hi - lo) * side_;
    return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(side_ - 1)));
  }
  Point2 lo_, hi_;
  int side_ = 1;
  std::vector<std::vector<std::int32_t>> cells_;
};

// Whether two edges of the polygon cross at a point inside both (touching at a corner, or
// running along each other, is not a crossing: ear cutting handles those or refuses them).
void refuse_crossings(const std::vector<Point2>& q) {
  const std::size_t n = q.size();
  Grid grid(q, n);
  for (std::size_t e = 0; e < n; ++e) grid.insert_segment(q[e], q[(e + 1) % n], static_cast<std::int32_t>(e));
  for (const std::vector<std::int32_t>& cell : grid.cells())
    for (std::size_t i = 0; i < cell.size(); ++i)
      for (std::size_t j = i + 1; j < cell.size(); ++j) {
        const std::size_t e = static_cast<std::size_t>(cell[i]), f = static_cast<std::size_t>(cell[j]);
        if ((e + 1) % n == f || (f + 1) % n == e) continue;  // neighbours share a corner
        const Point2 &a = q[e], &b = q[(e + 1) % n], &c = q[f], &d = q[(f + 1) % n];
        const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
        if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
          throw InputError("crosses itself (its edges " + std::to_string(std::min(e, f)) + " and " +
                           std::to_string(std::max(e, f)) + " cross): it is not a disk; split it into simple polygons");
      }
}

// Ear cutting on the polygon q (counter-clockwise), best-shaped ear (in space, `corners`)
// first. Only corners that do not turn left can lie in an ear (a convex corner inside a
// triangle of the polygon brings a reflex one with it), so only those are looked for, in a grid.
class EarCutter {
 public:
  EarCutter(const std::vector<Point2>& q, const std::vector<Vec3>& corners)
      : q_(q), p_(corners), n_(q.size()), prev_(n_), next_(n_), stamp_(n_, 0), blocking_(n_, 0), alive_(n_, 1),
        slot_(n_, 0), grid_(q, n_) {
    for (std::size_t i = 0; i < n_; ++i) {
      prev_[i] = static_cast<std::int32_t>((i + n_ - 1) % n_);
      next_[i] = static_cast<std::int32_t>((i + 1) % n_);
    }
    alive_count_ = n_;
    for (std::size_t i = 0; i < n_; ++i) {
      blocking_[i] = !convex(static_cast<std::int32_t>(i));
      if (blocking_[i]) {
        std::vector<std::int32_t>& cell = grid_.cell(grid_.cell_of(q_[i]));
        slot_[i] = cell.size();
        cell.push_back(static_cast<std::int32_t>(i));
        ++blocking_count_;
      }
    }
  }

  std::vector<std::array<std::int32_t, 3>> cut() {
    std::vector<std::array<std::int32_t, 3>> out;
    out.reserve(n_ - 2);
    refill();
    std::size_t left = n_;
    std::int32_t any = 0;
    while (left > 3) {
      if (ears_.empty() && !refill()) stuck();
      const auto [quality, v, stamp] = ears_.top();
      ears_.pop();
      if (!alive_[static_cast<std::size_t>(v)] || stamp != stamp_[static_cast<std::size_t>(v)] || !leaves_a_convex_corner(v))
        continue;
      const std::int32_t a = prev_[static_cast<std::size_t>(v)], b = next_[static_cast<std::size_t>(v)];
      out.push_back({a, v, b});
      alive_[static_cast<std::size_t>(v)] = 0;
      --alive_count_;
      next_[static_cast<std::size_t>(a)] = b;
      prev_[static_cast<std::size_t>(b)] = a;
      --left;
      any = a;
      for (const std::int32_t w : {a, b}) {
        const auto k = static_cast<std::size_t>(w);
        if (blocking_[k] && convex(w)) unblock(w);  // reflex corners only ever turn convex
        ++stamp_[k];
        push_if_ear(w);
      }
    }
    const std::int32_t a = prev_[static_cast<std::size_t>(any)], b = next_[static_cast<std::size_t>(any)];
    if (!convex(any)) stuck();
    out.push_back({a, any, b});
    return out;
  }

 private:
  using Ear = std::tuple<double, std::int32_t, std::uint32_t>;
  static constexpr double kNear = 1e-9;  // a distance in the plane that is rounding

  // Turns left by more than rounding (the sine of its angle above 1e-12).
  bool convex(std::int32_t v) const {
    const Point2 &a = q_[static_cast<std::size_t>(prev_[static_cast<std::size_t>(v)])], &b = q_[static_cast<std::size_t>(v)],
                 &c = q_[static_cast<std::size_t>(next_[static_cast<std::size_t>(v)])];
    const double scale = std::hypot(b.x - a.x, b.y - a.y) * std::hypot(c.x - b.x, c.y - b.y);
    return orient(a, b, c) > 1e-12 * scale;
  }

  bool is_ear(std::int32_t v) const {
    if (!convex(v)) return false;
    if (blocking_count_ == 0) return true;  // what is left is convex
    const std::int32_t ia = prev_[static_cast<std::size_t>(v)], ic = next_[static_cast<std::size_t>(v)];
    const Point2 &a = q_[static_cast<std::size_t>(ia)], &b = q_[static_cast<std::size_t>(v)], &c = q_[static_cast<std::size_t>(ic)];
    const Point2 lo{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y})};
    const Point2 hi{std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y})};
    const double ab = std::hypot(b.x - a.x, b.y - a.y), bc = std::hypot(c.x - b.x, c.y - b.y),
                 ca = std::hypot(a.x - c.x, a.y - c.y);
    const std::array<int, 4> r = grid_.range(Point2{lo.x - kNear, lo.y - kNear}, Point2{hi.x + kNear, hi.y + kNear});
    for (int i = r[0]; i <= r[1]; ++i)
      for (int j = r[2]; j <= r[3]; ++j)
        for (const std::int32_t w : grid_.at(i, j)) {
          const auto k = static_cast<std::size_t>(w);
          if (!alive_[k] || !blocking_[k] || w == ia || w == v || w == ic) continue;
          const Point2& p = q_[k];
          if (same(p, a) || same(p, b) || same(p, c)) continue;  // the same point, named twice
          if (p.x < lo.x - kNear || p.x > hi.x + kNear || p.y < lo.y - kNear || p.y > hi.y + kNear) continue;
          // Inside, on the triangle's boundary or within rounding of it (the polygon is of unit
          // size): cutting it off would overlap the rest, or leave it a zero-width spike.
          if (orient(a, b, p) >= -kNear * ab && orient(b, c, p) >= -kNear * bc && orient(c, a, p) >= -kNear * ca)
            return false;
        }
    return true;
  }

  // The ear's shape in space: 4√3 area / (sum of squared edges), 1 for an equilateral triangle.
  double quality(std::int32_t v) const {
    const Vec3 &a = p_[static_cast<std::size_t>(prev_[static_cast<std::size_t>(v)])], &b = p_[static_cast<std::size_t>(v)],
               &c = p_[static_cast<std::size_t>(next_[static_cast<std::size_t>(v)])];
    const double edges = dot(b - a, b - a) + dot(c - b, c - b) + dot(a - c, a - c);
    return edges > 0 ? 2 * std::sqrt(3.0) * norm(cross(b - a, c - a)) / edges : 0;
  }

  void push_if_ear(std::int32_t v) {
    if (is_ear(v)) ears_.emplace(quality(v), v, stamp_[static_cast<std::size_t>(v)]);
  }

  // A corner that turns left by more than rounding, where b's neighbours are a and c.
  bool turns_left(std::int32_t a, std::int32_t b, std::int32_t c) const {
    const Point2 &p = q_[static_cast<std::size_t>(a)], &q = q_[static_cast<std::size_t>(b)], &r = q_[static_cast<std::size_t>(c)];
    return orient(p, q, r) > 1e-12 * std::hypot(q.x - p.x, q.y - p.y) * std::hypot(r.x - q.x, r.y - q.y);
  }

  // Whether some corner still turns left after cutting v's ear. Cutting the last one off a line
  // of corners would leave them with no area, and the end a triangle of zero area; another ear
  // always remains.
  bool leaves_a_convex_corner(std::int32_t v) const {
    const std::int32_t a = prev_[static_cast<std::size_t>(v)], b = next_[static_cast<std::size_t>(v)];
    const std::int32_t before = 1 + convex(a) + convex(b);
    const std::int32_t after = turns_left(prev_[static_cast<std::size_t>(a)], a, b) + turns_left(a, b, next_[static_cast<std::size_t>(b)]);
    return convex_corners() - before + after > 0;
  }

  std::int64_t convex_corners() const { return static_cast<std::int64_t>(alive_count_) - blocking_count_; }

  // A reflex corner turned convex: out of the grid (swapped with the last of its cell).
  void unblock(std::int32_t v) {
    const auto k = static_cast<std::size_t>(v);
    std::vector<std::int32_t>& cell = grid_.cell(grid_.cell_of(q_[k]));
    cell[slot_[k]] = cell.back();
    slot_[static_cast<std::size_t>(cell.back())] = slot_[k];
    cell.pop_back();
    blocking_[k] = 0;
    --blocking_count_;
  }

  // Every ear again (a corner's ear can also open when a corner inside it turns convex), those
  // that leave a corner turning left.
  bool refill() {
    for (std::size_t i = 0; i < n_; ++i)
      if (alive_[i] && leaves_a_convex_corner(static_cast<std::int32_t>(i))) push_if_ear(static_cast<std::int32_t>(i));
    return !ears_.empty();
  }

  [[noreturn]] static void stuck() {
    throw InputError("cannot be split into triangles without overlaps: corners in line or touching each other "
                     "leave no triangle to cut");
  }

  const std::vector<Point2>& q_;
  const std::vector<Vec3>& p_;
  std::size_t n_;
  std::vector<std::int32_t> prev_, next_;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::uint8_t> blocking_, alive_;
  std::priority_queue<Ear> ears_;
  std::vector<std::size_t> slot_;  // a blocking corner's place in its grid cell
  Grid grid_;
  std::size_t alive_count_ = 0;
  std::int64_t blocking_count_ = 0;
};

}  // namespace

PolygonTriangles triangulate_polygon(const std::vector<Vec3>& corners) {
  const std::size_t n = corners.size();
  if (n < 3) throw InputError("has " + std::to_string(n) + " corners; a polygon needs at least 3");
  PolygonTriangles out;
  // Centred and scaled to unit size: no overflow or underflow whatever the coordinates' scale.
  Vec3 centre;
  for (const Vec3& p : corners) centre += p * (1.0 / static_cast<double>(n));
  double scale = 0;
  for (const Vec3& p : corners) {
    const Vec3 d = p - centre;
    scale = std::max({scale, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  }
  if (!(scale > 0) || !std::isfinite(scale)) throw InputError("has no area: all its corners are at one point");
  std::vector<Vec3> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = (corners[i] - centre) * (1.0 / scale);
  // Newell's normal: the area vector, whatever the polygon's shape (twice the area).
  Vec3 area;
  for (std::size_t i = 0; i < n; ++i) area += cross(p[i], p[(i + 1) % n]);
  if (!(norm(area) > 1e-12)) throw InputError("has no area as a polygon: its corners are in line, or it crosses itself");
  const Vec3 normal = area * (1.0 / norm(area));
  const Vec3 helper = std::abs(normal.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 u = cross(helper, normal) * (1.0 / norm(cross(helper, normal))), v = cross(normal, u);
  std::vector<Point2> q(n);
  double offset = 0, lo[3] = {1, 1, 1}, hi[3] = {-1, -1, -1};
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = {dot(p[i], u), dot(p[i], v)};  // counter-clockwise: the area vector is +normal
    offset = std::max(offset, std::abs(dot(p[i], normal)));
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[i][k]), hi[k] = std::max(hi[k], p[i][k]);
  }
  out.out_of_plane = offset / std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);

  if (n == 3) {
    out.triangles = {{0, 1, 2}};
    return out;
  }
  // The turns: a simple polygon turns once around (2π); all left turns and once around is convex.
  bool all_left = true;
  double turning = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 &a = q[(i + n - 1) % n], &b = q[i], &c = q[(i + 1) % n];
    const double turn = orient(a, b, c), along = (b.x - a.x) * (c.x - b.x) + (b.y - a.y) * (c.y - b.y);
    all_left = all_left && turn > 1e-12 * std::hypot(b.x - a.x, b.y - a.y) * std::hypot(c.x - b.x, c.y - b.y);
    turning += std::atan2(turn, along);
  }
  const double turns = turning / (2 * M_PI);
  if (std::abs(turns - 1) > 0.25)
    throw InputError("crosses itself: it winds " + std::to_string(static_cast<long>(std::lround(turns))) +
                     " times around its centre, not once; it is not a disk");
  const bool warped = out.out_of_plane > kWarpedPolygon;
  if (all_left && !warped) {
    for (std::size_t i = 1; i + 1 < n; ++i)
      out.triangles.push_back({0, static_cast<std::int32_t>(i), static_cast<std::int32_t>(i + 1)});
    return out;
  }
  refuse_crossings(q);
  out.split = warped ? PolygonSplit::warped_ears : PolygonSplit::ears;
  out.triangles = EarCutter(q, p).cut();
  return out;
}

}  // namespace rgbmesh
