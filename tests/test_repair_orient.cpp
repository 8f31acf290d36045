// rgbmesh::repair::orient_triangles against CGAL's orient_polygon_soup, the reference whose rule
// it follows: on random soups with reversed triangles, non-manifold edges and vertices, Möbius
// strips and tangles, both must give the same triangles, the same new points (copies of the
// same vertices, in the same order) and the same counts. Also: what comes out is an oriented
// surface wherever nothing was cut (each edge of two triangles run both ways).

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "rgbmesh/repair/orient_triangles.hpp"

namespace {

using rgbmesh::repair::orient_triangles;
using rgbmesh::repair::SoupOrientation;
using Triangle = std::array<std::size_t, 3>;
using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
namespace PMP = CGAL::Polygon_mesh_processing;

struct Reference : public PMP::Default_orientation_visitor {
  explicit Reference(SoupOrientation* into, std::set<std::pair<std::size_t, std::size_t>>* edges)
      : counts(into), non_manifold(edges) {}
  void non_manifold_edge(std::size_t a, std::size_t b, std::size_t) {
    non_manifold->insert({std::min(a, b), std::max(a, b)});
  }
  void non_manifold_vertex(std::size_t, std::size_t fans) {
    ++counts->split_vertices;
    counts->vertex_copies += fans;
  }
  void duplicated_vertex(std::size_t from, std::size_t) { counts->copied_from.push_back(from); }
  void polygon_orientation_reversed(std::size_t) { ++counts->reversed_triangles; }
  SoupOrientation* counts;
  std::set<std::pair<std::size_t, std::size_t>>* non_manifold;
};

// A torus grid of rows x columns quads, each split in two.
std::vector<Triangle> grid(std::size_t rows, std::size_t columns) {
  std::vector<Triangle> t;
  const auto id = [&](std::size_t i, std::size_t j) { return (i % rows) * columns + j % columns; };
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < columns; ++j) {
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

// A Möbius band of rows x columns quads (rows + 1 vertices across): the last column of quads
// closes onto the first with the rows reversed.
std::vector<Triangle> moebius(std::size_t rows, std::size_t columns) {
  std::vector<Triangle> t;
  const auto id = [&](std::size_t i, std::size_t j) {
    return j < columns ? i * columns + j : (rows - i) * columns;
  };
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < columns; ++j) {
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

// A random soup: a torus grid or a Möbius band (non-orientable), triangles reversed, extra
// triangles on existing edges (non-manifold edges), vertices merged (non-manifold vertices), a
// few random triangles; no triangle twice in any orientation.
std::vector<Triangle> random_soup(std::mt19937& rng, std::size_t& point_count) {
  std::uniform_int_distribution<std::size_t> size(2, 9);
  const std::size_t rows = size(rng) + 1, columns = size(rng) + 1;
  std::uniform_real_distribution<double> unit(0, 1);
  const bool band = unit(rng) < 0.3;
  std::vector<Triangle> t = band ? moebius(rows, columns) : grid(rows, columns);
  point_count = band ? (rows + 1) * columns : rows * columns;
  const double reverse = unit(rng) * 0.5, extra = unit(rng) * 0.1, merge = unit(rng) * 0.1;
  for (Triangle& f : t)
    if (unit(rng) < reverse) std::swap(f[1], f[2]);
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; ++i)
    if (unit(rng) < extra) t.push_back({t[i][0], t[i][1], point_count++});
  std::uniform_int_distribution<std::size_t> any(0, point_count - 1);
  for (std::size_t k = 0; k < static_cast<std::size_t>(merge * static_cast<double>(point_count)); ++k) {
    const std::size_t a = any(rng), b = any(rng);
    for (Triangle& f : t) std::replace(f.begin(), f.end(), b, a);
  }
  if (unit(rng) < 0.2)
    for (int k = 0; k < 5; ++k) t.push_back({any(rng), any(rng), any(rng)});
  // Three distinct corners, no repeats in either orientation (what repair hands on).
  std::vector<Triangle> kept;
  std::set<Triangle> seen;
  for (const Triangle& f : t) {
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) continue;
    Triangle key = f;
    std::sort(key.begin(), key.end());
    if (seen.insert(key).second) kept.push_back(f);
  }
  return kept;
}

// Edges of exactly two triangles in `before` that those two triangles (same index) no longer share
// in `after`, with `original` mapping the new points back: the cuts CGAL made (it does not
// count them).
std::size_t cut_edges(const std::vector<Triangle>& before, const std::vector<Triangle>& after,
                      const std::vector<std::size_t>& copied_from, std::size_t point_count) {
  const auto original = [&](std::size_t v) { return v < point_count ? v : copied_from[v - point_count]; };
  using Edge = std::pair<std::size_t, std::size_t>;
  const auto edge = [](std::size_t a, std::size_t b) { return Edge{std::min(a, b), std::max(a, b)}; };
  std::map<Edge, std::vector<std::size_t>> sides;
  for (std::size_t t = 0; t < before.size(); ++t)
    for (int k = 0; k < 3; ++k) sides[edge(before[t][k], before[t][(k + 1) % 3])].push_back(t);
  // The edge e of triangle t as it is now, in the new numbers.
  const auto now = [&](std::size_t t, const Edge& e) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = after[t][k], b = after[t][(k + 1) % 3];
      if (edge(original(a), original(b)) == e) return edge(a, b);
    }
    return Edge{};
  };
  std::size_t cut = 0;
  for (const auto& [e, along] : sides)
    if (along.size() == 2 && now(along[0], e) != now(along[1], e)) ++cut;
  return cut;
}

TEST(RepairOrient, GivesCgalsTrianglesNewPointsAndCountsOnRandomSoups) {
  std::mt19937 rng(20261206);
  std::size_t reversed = 0, copies = 0, non_manifold = 0, cuts = 0, exact_cuts = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::size_t point_count = 0;
    const std::vector<Triangle> soup = random_soup(rng, point_count);

    std::vector<Triangle> ours = soup;
    const SoupOrientation mine = orient_triangles(ours, point_count);

    std::vector<Point> points;
    for (std::size_t i = 0; i < point_count; ++i) points.emplace_back(double(i), double(i * i % 7), 0.0);
    std::vector<Triangle> theirs = soup;
    SoupOrientation reference;
    std::set<std::pair<std::size_t, std::size_t>> edges;
    PMP::orient_polygon_soup(points, theirs, CGAL::parameters::visitor(Reference(&reference, &edges)));
    reference.non_manifold_edges = edges.size();

    ASSERT_EQ(ours, theirs) << "trial " << trial;
    ASSERT_EQ(mine.copied_from, reference.copied_from) << "trial " << trial;
    ASSERT_EQ(points.size(), point_count + mine.copied_from.size()) << "trial " << trial;
    EXPECT_EQ(mine.reversed_triangles, reference.reversed_triangles) << "trial " << trial;
    EXPECT_EQ(mine.split_vertices, reference.split_vertices) << "trial " << trial;
    EXPECT_EQ(mine.vertex_copies, reference.vertex_copies) << "trial " << trial;
    EXPECT_EQ(mine.non_manifold_edges, reference.non_manifold_edges) << "trial " << trial;
    // Our count of cuts is the walk's; where the split vertices separate the two triangles of
    // every cut edge, it is CGAL's result's too.
    const std::size_t separated = cut_edges(soup, theirs, reference.copied_from, point_count);
    EXPECT_GE(mine.cut_edges, separated) << "trial " << trial;
    exact_cuts += mine.cut_edges == separated;
    cuts += mine.cut_edges;
    reversed += mine.reversed_triangles, copies += mine.copied_from.size(),
        non_manifold += mine.non_manifold_edges;
  }
  // The soups exercised every part of the rule.
  EXPECT_GT(reversed, 1000u);
  EXPECT_GT(copies, 100u);
  EXPECT_GT(non_manifold, 100u);
  EXPECT_GT(cuts, 20u);
  EXPECT_GT(exact_cuts, 360u);
  std::printf(
      "  400 soups: %zu triangles reversed, %zu vertex copies, %zu non-manifold edges, %zu cuts "
      "(all separated in %zu soups)\n",
      reversed, copies, non_manifold, cuts, exact_cuts);
}

TEST(RepairOrient, AnOrientableSoupComesOutAsAnOrientedSurface) {
  std::mt19937 rng(7);
  std::vector<Triangle> t = grid(12, 17);
  std::bernoulli_distribution flip(0.4);
  for (std::size_t i = 1; i < t.size(); ++i)  // (the first stays as built: the others follow it)
    if (flip(rng)) std::swap(t[i][0], t[i][2]);
  const SoupOrientation result = orient_triangles(t, 12 * 17);
  EXPECT_TRUE(result.copied_from.empty());
  EXPECT_EQ(result.non_manifold_edges, 0u);
  std::map<std::pair<std::size_t, std::size_t>, int> directed;
  for (const Triangle& f : t)
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "a closed torus: every edge run both ways";
  }
  EXPECT_EQ(t, grid(12, 17)) << "every triangle should be back as built, like the first";
}

}  // namespace
