// Polygons into triangles (polygons.hpp): every polygon of many shapes (stars, combs, spirals,
// random simple polygons, corners in line), placed anywhere in space at any scale, is covered
// exactly once, checked against an independent winding-number count and the disk's edges;
// self-crossing polygons are refused; warped polygons are split into a disk.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "rgbmesh/polygons.hpp"
#include "rgbmesh/soup.hpp"

namespace {

using rgbmesh::InputError;
using rgbmesh::PolygonSplit;
using rgbmesh::PolygonTriangles;
using rgbmesh::triangulate_polygon;
using rgbmesh::Vec3;

struct P2 {
  double x, y;
};
using Polygon2 = std::vector<P2>;

double cross2(const P2& a, const P2& b, const P2& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

double signed_area(const Polygon2& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) a += p[i].x * p[(i + 1) % p.size()].y - p[(i + 1) % p.size()].x * p[i].y;
  return a / 2;
}

// The winding number of the polygon around q (Sunday's crossing rule), the reference for which
// points the polygon covers.
int winding(const Polygon2& p, const P2& q) {
  int w = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const P2 &a = p[i], &b = p[(i + 1) % p.size()];
    if (a.y <= q.y) {
      if (b.y > q.y && cross2(a, b, q) > 0) ++w;
    } else if (b.y <= q.y && cross2(a, b, q) < 0) {
      --w;
    }
  }
  return w;
}

Polygon2 star(int points, double inner) {
  Polygon2 p;
  for (int i = 0; i < 2 * points; ++i) {
    const double r = i % 2 == 0 ? 1.0 : inner, t = M_PI * i / points;
    p.push_back({r * std::cos(t), r * std::sin(t)});
  }
  return p;
}

Polygon2 comb(int teeth) {
  Polygon2 p = {{0, 0}, {2.0 * teeth, 0}};
  for (int i = teeth; i > 0; --i) {
    p.push_back({2.0 * i, 5});
    p.push_back({2.0 * i - 1, 5});
    p.push_back({2.0 * i - 1, 1});
    if (i > 1) p.push_back({2.0 * i - 2, 1});
  }
  p.push_back({0, 5});
  return p;
}

// A band wound `turns` times around the origin, growing outwards (it never meets itself).
Polygon2 spiral(double turns, int steps) {
  Polygon2 outer, inner;
  for (int k = 0; k <= steps; ++k) {
    const double t = 2 * M_PI * turns * k / steps, r = 1 + 0.5 * t;
    outer.push_back({r * std::cos(t), r * std::sin(t)});
    inner.push_back({(r - 0.6) * std::cos(t), (r - 0.6) * std::sin(t)});
  }
  std::reverse(inner.begin(), inner.end());
  outer.insert(outer.end(), inner.begin(), inner.end());
  return outer;
}

// Random points untangled by 2-opt moves into a simple polygon (each move shortens the tour).
Polygon2 random_simple(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Polygon2 p(static_cast<std::size_t>(n));
  for (P2& q : p) q = {u(rng), u(rng)};
  const auto crossing = [](const P2& a, const P2& b, const P2& c, const P2& d) {
    return cross2(a, b, c) * cross2(a, b, d) < 0 && cross2(c, d, a) * cross2(c, d, b) < 0;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (int i = 0; i < n; ++i)
      for (int j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;
        if (crossing(p[i], p[i + 1], p[j], p[(j + 1) % n])) {
          std::reverse(p.begin() + i + 1, p.begin() + j + 1);
          changed = true;
        }
      }
  }
  return p;
}

// A square with extra corners along its edges and a notch: corners in line everywhere.
Polygon2 square_with_corners_in_line() {
  return {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2}, {3, 3}, {2, 3}, {2, 1.5}, {1, 1.5}, {1, 3}, {0, 3}, {0, 2}, {0, 1}};
}

// The polygon placed in space: rotated, scaled and moved.
struct Placement {
  Vec3 origin, u, v;
  double scale;
  Vec3 at(const P2& p) const { return origin + (u * p.x + v * p.y) * scale; }
};

Placement random_placement(std::mt19937& rng, double scale) {
  std::normal_distribution<double> g(0, 1);
  Vec3 a(g(rng), g(rng), g(rng)), b(g(rng), g(rng), g(rng));
  a = a * (1 / rgbmesh::norm(a));
  b = b - a * rgbmesh::dot(a, b);
  b = b * (1 / rgbmesh::norm(b));
  return {Vec3(g(rng), g(rng), g(rng)) * scale, a, b, scale};
}

// Checks that the triangles cover the polygon exactly once: n - 2 of them; each turns as the
// polygon does with positive area; every boundary edge used once in its direction, every other
// edge twice in opposite directions (a disk); the areas add up to the polygon's; and at random
// points, the number of triangles containing the point equals the polygon's winding number.
void expect_covered_once(const Polygon2& polygon, const PolygonTriangles& split, const std::string& what) {
  const std::size_t n = polygon.size();
  ASSERT_EQ(split.triangles.size(), n - 2) << what;
  std::map<std::pair<int, int>, int> directed;
  double area = 0;
  for (const auto& t : split.triangles) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(t[k], 0) << what;
      ASSERT_LT(t[k], static_cast<int>(n)) << what;
      ++directed[{t[k], t[(k + 1) % 3]}];
    }
    const double a = cross2(polygon[t[0]], polygon[t[1]], polygon[t[2]]) / 2;
    EXPECT_GT(a, 0) << what << ": a triangle turns the wrong way or has no area";
    area += a;
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << what << ": edge " << edge.first << "-" << edge.second << " used twice in one direction";
    const bool boundary = (edge.first + 1) % static_cast<int>(n) == edge.second;
    if (!boundary) {
      EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << what << ": an inner edge on one side only";
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_EQ(directed.count({static_cast<int>(i), static_cast<int>((i + 1) % n)}), 1u) << what << ": boundary edge " << i;
  EXPECT_NEAR(area, signed_area(polygon), 1e-9 * std::abs(signed_area(polygon))) << what;
  // Coverage at random points of the bounding box.
  P2 lo = polygon[0], hi = polygon[0];
  for (const P2& p : polygon) lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y);
  for (int s = 0; s < 2000; ++s) {
    const P2 q{ux(rng), uy(rng)};
    int inside = 0;
    for (const auto& t : split.triangles)
      inside += cross2(polygon[t[0]], polygon[t[1]], q) > 0 && cross2(polygon[t[1]], polygon[t[2]], q) > 0 &&
                cross2(polygon[t[2]], polygon[t[0]], q) > 0;
    ASSERT_EQ(inside, winding(polygon, q)) << what << ": point (" << q.x << ", " << q.y << ")";
  }
}

std::vector<std::pair<std::string, Polygon2>> shapes() {
  std::vector<std::pair<std::string, Polygon2>> out;
  for (const int points : {3, 5, 8, 40})
    for (const double inner : {0.2, 0.5, 0.9}) out.push_back({"star " + std::to_string(points) + "/" + std::to_string(inner), star(points, inner)});
  for (const int teeth : {1, 2, 7, 30}) out.push_back({"comb " + std::to_string(teeth), comb(teeth)});
  for (const double turns : {0.75, 1.5, 3.0}) out.push_back({"spiral " + std::to_string(turns), spiral(turns, static_cast<int>(60 * turns))});
  std::mt19937 rng(42);
  for (const int n : {6, 12, 25, 60, 120}) out.push_back({"random " + std::to_string(n), random_simple(n, rng)});
  out.push_back({"square with corners in line", square_with_corners_in_line()});
  return out;
}

TEST(Polygons, ConcavePolygonsOfManyShapesAreCoveredOnceAnywhereAtAnyScale) {
  std::mt19937 rng(1);
  for (const auto& [name, polygon] : shapes())
    for (const double scale : {1e-150, 1e-3, 1.0, 1e6, 1e150})
      for (const bool reversed : {false, true}) {
        Polygon2 p = polygon;
        if (reversed) std::reverse(p.begin(), p.end());  // clockwise in the plane: seen from the other side
        const Placement place = random_placement(rng, scale);
        std::vector<Vec3> corners;
        for (const P2& q : p) corners.push_back(place.at(q));
        const std::string what = name + (reversed ? " reversed" : "") + " at scale " + std::to_string(scale);
        const PolygonTriangles split = triangulate_polygon(corners);
        EXPECT_LT(split.out_of_plane, 1e-12) << what;
        // The check in the polygon's own turning: a clockwise one (reversed, or random) is
        // seen from the other side of its plane.
        Polygon2 turning = p;
        if (signed_area(p) < 0)
          for (P2& q : turning) q.y = -q.y;
        expect_covered_once(turning, split, what);
      }
}

TEST(Polygons, PlanarConvexPolygonsAreFansAsBefore) {
  Polygon2 regular;
  for (int i = 0; i < 7; ++i) regular.push_back({std::cos(2 * M_PI * i / 7), std::sin(2 * M_PI * i / 7)});
  std::vector<Vec3> corners;
  for (const P2& q : regular) corners.push_back({q.x, q.y, 3});
  const PolygonTriangles split = triangulate_polygon(corners);
  EXPECT_EQ(split.split, PolygonSplit::fan);
  for (int i = 1; i + 1 < 7; ++i) EXPECT_EQ(split.triangles[static_cast<std::size_t>(i - 1)], (std::array<std::int32_t, 3>{0, i, i + 1}));
  // A concave one is not a fan.
  std::vector<Vec3> concave;
  for (const P2& q : star(5, 0.4)) concave.push_back({q.x, q.y, 0});
  EXPECT_EQ(triangulate_polygon(concave).split, PolygonSplit::ears);
}

TEST(Polygons, SelfCrossingPolygonsAreRefused) {
  Polygon2 pentagon, twice;
  for (int i = 0; i < 5; ++i) pentagon.push_back({std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5)});
  for (int i = 0; i < 10; ++i) twice.push_back({std::cos(4 * M_PI * i / 10 + 0.1), std::sin(4 * M_PI * i / 10 + 0.1)});
  const std::vector<std::pair<std::string, Polygon2>> crossing = {
      {"pentagram", {pentagon[0], pentagon[2], pentagon[4], pentagon[1], pentagon[3]}},
      {"bowtie", {{0, 0}, {1, 1}, {1, 0}, {0, 1}}},
      {"lopsided bowtie", {{0, 0}, {2, 2}, {2, 0}, {0, 1}}},
      {"winds twice", twice},
      // Turns once around, yet two spikes cross the bottom edge.
      {"spikes through an edge", {{0, 0}, {4, 0}, {4, 4}, {2, 4}, {2, -1}, {1, -1}, {1, 3}, {0, 3}}},
  };
  for (const auto& [name, p] : crossing) {
    std::vector<Vec3> corners;
    for (const P2& q : p) corners.push_back({q.x, 2 * q.y, q.x - q.y});
    try {
      triangulate_polygon(corners);
      ADD_FAILURE() << name << " was split";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("crosses itself") != std::string::npos || what.find("no area") != std::string::npos)
          << name << ": " << what;
    }
  }
}

TEST(Polygons, WarpedPolygonsAreSplitIntoADiskOfWellShapedTriangles) {
  // A hexagon whose corners go up and down (a saddle), and a warped quad.
  Polygon2 hexagon;
  std::vector<Vec3> saddle;
  for (int i = 0; i < 6; ++i) {
    hexagon.push_back({std::cos(M_PI * i / 3), std::sin(M_PI * i / 3)});
    saddle.push_back({hexagon.back().x, hexagon.back().y, i % 2 == 0 ? 0.3 : -0.3});
  }
  PolygonTriangles split = triangulate_polygon(saddle);
  EXPECT_EQ(split.split, PolygonSplit::warped_ears);
  EXPECT_NEAR(split.out_of_plane, 0.3 / std::hypot(2.0, std::sqrt(3.0), 0.6), 1e-12);
  expect_covered_once(hexagon, split, "saddle");
  // The quad's split is along the diagonal that gives the better-shaped triangles.
  const std::vector<Vec3> quad = {{0, 0, 0}, {3, 0, 0.5}, {3, 1, 0}, {0, 1, 0.5}};
  split = triangulate_polygon(quad);
  EXPECT_EQ(split.split, PolygonSplit::warped_ears);
  expect_covered_once({{0, 0}, {3, 0}, {3, 1}, {0, 1}}, split, "quad");
}

TEST(Polygons, LargePolygonsAreSplit) {
  // A convex 100,000-gon (a fan) and a star of 20,000 corners (ears, each reflex corner found
  // through the grid, not by a scan of all corners).
  std::vector<Vec3> circle;
  for (int i = 0; i < 100000; ++i) circle.push_back({std::cos(2 * M_PI * i / 100000), std::sin(2 * M_PI * i / 100000), 0});
  EXPECT_EQ(triangulate_polygon(circle).triangles.size(), 99998u);
  const Polygon2 big = star(10000, 0.95);
  std::vector<Vec3> corners;
  for (const P2& q : big) corners.push_back({q.x, q.y, 0});
  const PolygonTriangles split = triangulate_polygon(corners);
  ASSERT_EQ(split.triangles.size(), big.size() - 2);
  double area = 0;
  for (const auto& t : split.triangles) {
    const double a = cross2(big[t[0]], big[t[1]], big[t[2]]) / 2;
    EXPECT_GT(a, 0);
    area += a;
  }
  EXPECT_NEAR(area, signed_area(big), 1e-9 * signed_area(big));
}

TEST(Polygons, SoupsNameTheFaceAndCountTheKinds) {
  rgbmesh::PolygonSoup soup;
  const Polygon2 c = comb(3);
  for (const P2& q : c) soup.points.push_back({q.x, q.y, 0});
  std::vector<std::int64_t> face;
  for (std::size_t i = 0; i < c.size(); ++i) face.push_back(static_cast<std::int64_t>(i));
  soup.faces = {face};
  rgbmesh::SoupOptions options;
  options.triangulate = true;
  const rgbmesh::TriangleMeshData m = rgbmesh::prepare_triangle_mesh(soup, options);
  EXPECT_EQ(m.triangles.size(), c.size() - 2);
  ASSERT_FALSE(m.notes.empty());
  EXPECT_EQ(m.notes[0], "split 1 polygon into triangles (" + std::to_string(c.size() - 2) +
                            " triangles in all): 1 concave or with corners in line by cutting ears in their planes");
  // A pentagram face after a triangle: refused, naming face 1.
  rgbmesh::PolygonSoup crossing;
  for (int i = 0; i < 5; ++i) crossing.points.push_back({std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5), 0});
  crossing.faces = {{0, 1, 2}, {0, 2, 4, 1, 3}};
  try {
    rgbmesh::prepare_triangle_mesh(crossing, options);
    ADD_FAILURE() << "the pentagram was split";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("face 1 (a polygon of 5 vertices) crosses itself", 0), 0u) << e.what();
  }
}

}  // namespace
