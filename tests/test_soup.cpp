// prepare_triangle_mesh: every check names the offending element, the repairs do what the notes
// say, and the result is a manifold, consistently oriented mesh without unused vertices.
// RgbMesh::from_triangles: the same checks and messages, and rejections where the file path
// repairs.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/soup.hpp"

namespace {

using rgbmesh::InputError;
using rgbmesh::PolygonSoup;
using rgbmesh::prepare_triangle_mesh;
using rgbmesh::SoupOptions;
using rgbmesh::TriangleMeshData;
using rgbmesh::Vec3;
using Triangle = std::array<std::int32_t, 3>;

// The regular octahedron, counter-clockwise seen from outside.
PolygonSoup octahedron() {
  PolygonSoup s;
  s.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  s.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return s;
}

// The unit square split along its diagonal (0, 2).
PolygonSoup square() {
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.faces = {{0, 1, 2}, {0, 2, 3}};
  return s;
}

// The message of the InputError thrown by prepare_triangle_mesh, or "" if it succeeds. Any other
// exception type fails the test.
std::string error_of(const PolygonSoup& soup, const SoupOptions& options = {}) {
  try {
    prepare_triangle_mesh(soup, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Directed edge -> number of triangles running it; a consistently oriented manifold has every
// directed edge at most once.
std::map<std::pair<std::int32_t, std::int32_t>, int> directed_edges(const std::vector<Triangle>& triangles) {
  std::map<std::pair<std::int32_t, std::int32_t>, int> count;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++count[{t[k], t[(k + 1) % 3]}];
  return count;
}

void expect_clean(const TriangleMeshData& m) {
  for (const auto& [edge, n] : directed_edges(m.triangles))
    EXPECT_EQ(n, 1) << edge.first << "->" << edge.second;
  std::vector<bool> used(m.points.size(), false);
  for (const auto& t : m.triangles)
    for (const auto v : t) {
      ASSERT_GE(v, 0);
      ASSERT_LT(static_cast<std::size_t>(v), m.points.size());
      used[v] = true;
    }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

TEST(Soup, CleanMeshPassesUnchanged) {
  const PolygonSoup s = octahedron();
  const TriangleMeshData m = prepare_triangle_mesh(s);
  EXPECT_EQ(m.points, s.points);
  ASSERT_EQ(m.triangles.size(), s.faces.size());
  for (std::size_t t = 0; t < s.faces.size(); ++t)
    EXPECT_EQ(m.triangles[t],
              (Triangle{static_cast<std::int32_t>(s.faces[t][0]), static_cast<std::int32_t>(s.faces[t][1]),
                        static_cast<std::int32_t>(s.faces[t][2])}));
  EXPECT_TRUE(m.notes.empty());
}

TEST(Soup, EmptyMeshIsRejected) {
  PolygonSoup no_faces = octahedron();
  no_faces.faces.clear();
  EXPECT_EQ(error_of(no_faces), "the mesh is empty (6 vertices, 0 faces)");
  EXPECT_EQ(error_of(PolygonSoup{}), "the mesh is empty (0 vertices, 0 faces)");
}

TEST(Soup, NonFiniteCoordinateNamesTheVertex) {
  PolygonSoup s = octahedron();
  s.points[4] = {std::numeric_limits<double>::quiet_NaN(), 0, 1};
  EXPECT_EQ(error_of(s), "vertex 4 has a non-finite coordinate (nan, 0, 1)");
  s.points[4] = {0, -std::numeric_limits<double>::infinity(), 1};
  EXPECT_EQ(error_of(s), "vertex 4 has a non-finite coordinate (0, -inf, 1)");
  // Checked even for a vertex no face uses: such a value means the file is broken.
  s = octahedron();
  s.points.push_back({0, 0, std::numeric_limits<double>::infinity()});
  EXPECT_EQ(error_of(s), "vertex 6 has a non-finite coordinate (0, 0, inf)");
}

TEST(Soup, FaceWithTooFewVerticesIsRejected) {
  PolygonSoup s = octahedron();
  s.faces[3] = {3, 0};
  EXPECT_EQ(error_of(s), "face 3 has 2 vertices; a face needs at least 3");
  s.faces[3] = {};
  EXPECT_EQ(error_of(s), "face 3 has 0 vertices; a face needs at least 3");
}

TEST(Soup, IndexOutOfRangeNamesFaceAndVertex) {
  PolygonSoup s = octahedron();
  s.faces[5] = {1, 99, 5};
  EXPECT_EQ(error_of(s), "face 5 references vertex 99 but the file has 6 vertices");
  s.faces[5] = {1, -1, 5};
  EXPECT_EQ(error_of(s), "face 5 references vertex -1 but the file has 6 vertices");
  s.faces[5] = {1, std::numeric_limits<std::int64_t>::max(), 5};
  EXPECT_NE(error_of(s).find("face 5 references vertex 9223372036854775807"), std::string::npos);
}

TEST(Soup, ChecksRunInTheDocumentedOrder) {
  // A non-finite coordinate is reported before an out-of-range index in an earlier face, and a
  // short face before an out-of-range index.
  PolygonSoup s = octahedron();
  s.faces[0] = {0, 2, 40};
  s.points[5].z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_of(s).find("vertex 5 has a non-finite"), std::string::npos);
  s.points[5].z = -1;
  s.faces[7] = {0, 3};
  EXPECT_NE(error_of(s).find("face 7 has 2 vertices"), std::string::npos);
}

TEST(Soup, PolygonsNeedTriangulate) {
  PolygonSoup s = square();
  s.faces = {{0, 1, 2, 3}};
  EXPECT_EQ(error_of(s),
            "face 0 has 4 vertices; only triangles are supported (use --triangulate to split polygons)");
}

TEST(Soup, TriangulateFanSplitsPlanarConvexPolygons) {
  PolygonSoup s;
  // A pentagon (convex, counter-clockwise) followed by a triangle sharing its edge (1, 2).
  s.points = {{0, 0, 0}, {2, 0, 0}, {3, 2, 0}, {1, 3, 0}, {-1, 2, 0}, {3, -1, 0}};
  s.faces = {{0, 1, 2, 3, 4}, {1, 5, 2}};
  SoupOptions options;
  options.triangulate = true;
  const TriangleMeshData m = prepare_triangle_mesh(s, options);
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {1, 5, 2}}));
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_EQ(m.notes[0], "split 1 polygon into triangles (4 triangles in all): 1 planar and convex as fans");
  expect_clean(m);
}

TEST(Soup, ErrorsAfterTriangulationNameTheSourceFace) {
  PolygonSoup s = square();
  s.faces = {{0, 1, 2, 3}, {0, 2, 3}};  // the quad's second fan triangle equals face 1
  SoupOptions options;
  options.triangulate = true;
  EXPECT_EQ(error_of(s, options),
            "triangles 1 (from face 0) and 2 (from face 1) are duplicates (vertices 0, 2, 3)");
}

TEST(Soup, DegenerateTrianglesAreRejected) {
  PolygonSoup s = square();
  s.faces[1] = {0, 2, 0};
  EXPECT_EQ(error_of(s), "triangle 1 is degenerate: it repeats vertex 0 (0, 2, 0)");

  s = square();
  s.points.push_back({2, 2, 0});  // on the line through 0 and 2
  s.faces[1] = {0, 2, 4};
  EXPECT_EQ(error_of(s), "triangle 1 is degenerate: it has zero area (vertices 0, 2, 4 are collinear)");

  s = square();
  s.points.push_back({1, 1, 0});  // a second vertex at the position of vertex 2
  s.faces[1] = {0, 2, 4};
  EXPECT_EQ(error_of(s), "triangle 1 is degenerate: it has zero area (vertices 0, 2, 4 are collinear)");

  s = square();
  s.points = {{5, 5, 5}, {5, 5, 5}, {5, 5, 5}};
  s.faces = {{0, 1, 2}};
  EXPECT_EQ(error_of(s), "triangle 0 is degenerate: its vertices 0, 1, 2 are all at (5, 5, 5)");
}

TEST(Soup, ZeroAreaThresholdIsRelativeToTheLongestEdge) {
  // Height h over a base of length 1: area h/2, longest edge ~1, so the threshold is h = 2e-14.
  for (const double scale : {1e-100, 1.0, 1e100}) {
    PolygonSoup s;
    s.faces = {{0, 1, 2}};
    s.points = {{0, 0, 0}, {scale, 0, 0}, {0.5 * scale, 1e-14 * scale, 0}};
    EXPECT_NE(error_of(s).find("zero area"), std::string::npos) << scale;
    s.points[2].y = 1e-12 * scale;  // thin, but a real triangle
    EXPECT_EQ(error_of(s), "") << scale;
  }
  // Coordinates near the top of the double range neither overflow nor count as degenerate.
  PolygonSoup huge;
  huge.faces = {{0, 1, 2}};
  huge.points = {{-1e308, -1e308, 0}, {1e308, -1e308, 0}, {0, 1e308, 0}};
  EXPECT_EQ(error_of(huge), "");
}

TEST(Soup, DuplicateTrianglesAreRejectedInAnyVertexOrder) {
  PolygonSoup s = octahedron();
  s.faces.push_back({4, 0, 2});  // face 0 rotated
  EXPECT_EQ(error_of(s), "triangles 0 and 8 are duplicates (vertices 0, 2, 4)");
  s = octahedron();
  s.faces.push_back({2, 0, 4});  // face 0 reversed
  EXPECT_EQ(error_of(s), "triangles 0 and 8 are duplicates (vertices 0, 2, 4)");
}

TEST(Soup, NonManifoldEdgeNamesEdgeAndTriangles) {
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {2, 3, 4}, {0, 1, 4}};
  EXPECT_EQ(error_of(s), "edge (0, 1) is shared by 3 triangles: 0, 1, 3");
}

TEST(Soup, NonManifoldVertexCountsTheFans) {
  // Two triangles touching only at vertex 0 (a bow tie).
  PolygonSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_EQ(error_of(s), "vertex 0 is non-manifold: its triangles form 2 separate fans");
  // Two closed cones sharing their apex 0: three fans once a third disk is added.
  s.points = {{0, 0, 0},   {1, 0, 1},    {-1, 1, 1}, {-1, -1, 1}, {1, 0, -1},
              {-1, 1, -1}, {-1, -1, -1}, {2, 0, 0},  {2, 1, 0}};
  s.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {0, 5, 4}, {0, 6, 5}, {0, 4, 6}, {0, 7, 8}};
  EXPECT_EQ(error_of(s), "vertex 0 is non-manifold: its triangles form 3 separate fans");
}

TEST(Soup, MoebiusStripIsNotOrientable) {
  // A strip of 6 quads (12 triangles) whose ends are glued with a half twist.
  const int n = 6;
  PolygonSoup s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, half = a / 2;
    for (const double w : {-0.3, 0.3})
      s.points.push_back({(1 + w * std::cos(half)) * std::cos(a), (1 + w * std::cos(half)) * std::sin(a),
                          w * std::sin(half)});
  }
  for (int i = 0; i < n; ++i) {
    const std::int64_t a0 = 2 * i, a1 = 2 * i + 1;
    // The last quad joins the inner rim to the outer one: the half twist.
    const std::int64_t b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    s.faces.push_back({a0, b0, b1});
    s.faces.push_back({a0, b1, a1});
  }
  const std::string error = error_of(s);
  EXPECT_EQ(error.rfind("the surface is not orientable (Möbius-like): triangle ", 0), 0u) << error;
  EXPECT_NE(error.find("cannot be oriented consistently"), std::string::npos) << error;
}

TEST(Soup, InconsistentOrientationIsRepairedPerComponent) {
  // Two octahedra; in the first, triangles 2 and 5 are flipped; in the second, its lowest
  // triangle (8) is flipped, so all its other triangles must be flipped to match it.
  const PolygonSoup o = octahedron();
  PolygonSoup s = o;
  for (const auto& p : o.points) s.points.push_back(p + Vec3(5, 0, 0));
  for (auto f : o.faces) {
    for (auto& v : f) v += 6;
    s.faces.push_back(f);
  }
  for (const int t : {2, 5, 8}) std::swap(s.faces[t][1], s.faces[t][2]);
  const TriangleMeshData m = prepare_triangle_mesh(s);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_EQ(m.notes[0], "re-oriented 9 triangles for a consistent orientation");
  expect_clean(m);
  for (int t = 0; t < 8; ++t) {
    const auto& f = o.faces[t];
    EXPECT_EQ(m.triangles[t], (Triangle{static_cast<std::int32_t>(f[0]), static_cast<std::int32_t>(f[1]),
                                        static_cast<std::int32_t>(f[2])}))
        << t;
    // Second component: every triangle is the original reversed (as triangle 8 was).
    const Triangle reversed = {static_cast<std::int32_t>(f[0] + 6), static_cast<std::int32_t>(f[2] + 6),
                               static_cast<std::int32_t>(f[1] + 6)};
    EXPECT_EQ(m.triangles[t + 8], reversed) << t + 8;
  }
}

TEST(Soup, UnreferencedVerticesAreDroppedAndTheRestRenumbered) {
  PolygonSoup s = square();
  s.points.insert(s.points.begin() + 1, {7, 7, 7});  // new vertex 1
  s.points.push_back({8, 8, 8});                     // new vertex 5
  s.faces = {{0, 2, 3}, {0, 3, 4}};
  const TriangleMeshData m = prepare_triangle_mesh(s);
  EXPECT_EQ(m.points, square().points);
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_EQ(m.notes[0], "dropped 2 unreferenced vertices (first: 1)");
}

// A w x h grid of quads, each split into two triangles, with every third triangle flipped.
PolygonSoup flipped_grid(int w, int h) {
  PolygonSoup s;
  s.points.reserve(static_cast<std::size_t>(w + 1) * (h + 1));
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) s.points.push_back({double(i), double(j), 0.01 * ((i * 7 + j * 3) % 5)});
  const auto id = [w](int i, int j) { return static_cast<std::int64_t>(j) * (w + 1) + i; };
  s.faces.reserve(2 * static_cast<std::size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (std::size_t t = 1; t < s.faces.size(); t += 3) std::swap(s.faces[t][1], s.faces[t][2]);
  return s;
}

// Its time against the mesh size is a benchmark (BM_PrepareTriangleMesh in bench/bench_refinement.cpp).
TEST(Soup, AMillionTrianglesAreOrientedConsistently) {
  const PolygonSoup s = flipped_grid(1000, 500);
  const TriangleMeshData m = prepare_triangle_mesh(s);
  ASSERT_EQ(m.triangles.size(), 1000000u);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_EQ(m.notes[0], "re-oriented 333333 triangles for a consistent orientation");
  // Triangle 0 keeps its orientation: its normal points up (+z), and so must every other.
  for (const auto& t : m.triangles) {
    const Vec3 n = rgbmesh::cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    ASSERT_GT(n.z, 0);
  }
}

// Random soups, sometimes valid, mostly broken: the result is either an InputError or a clean
// mesh, never a crash, a hang or another exception.
TEST(Soup, RandomSoupsGiveAnErrorOrACleanMesh) {
  std::mt19937 rng(12345);
  int accepted = 0;
  for (int round = 0; round < 3000; ++round) {
    PolygonSoup s;
    if (round % 2 == 0) {
      // Start from a valid mesh and damage it a little.
      s = flipped_grid(3, 2);
      const int edits = static_cast<int>(rng() % 3);
      for (int e = 0; e < edits; ++e) {
        auto& f = s.faces[rng() % s.faces.size()];
        switch (rng() % 5) {
          case 0:
            f[rng() % 3] = static_cast<std::int64_t>(rng() % 14) - 1;
            break;
          case 1:
            f.pop_back();
            break;
          case 2:
            f.push_back(static_cast<std::int64_t>(rng() % 12));
            break;
          case 3:
            s.faces.push_back(f);
            break;
          default:
            s.points.push_back({double(rng() % 3), 0, 0});
            break;
        }
      }
    } else {
      const std::size_t n_points = rng() % 8, n_faces = rng() % 10;
      for (std::size_t i = 0; i < n_points; ++i)
        s.points.push_back({double(rng() % 3), double(rng() % 3), double(rng() % 3)});
      for (std::size_t i = 0; i < n_faces; ++i) {
        std::vector<std::int64_t> f(2 + rng() % 3);
        for (auto& v : f) v = static_cast<std::int64_t>(rng() % (n_points + 2)) - 1;
        s.faces.push_back(f);
      }
    }
    SoupOptions options;
    options.triangulate = rng() % 2 == 0;
    try {
      const TriangleMeshData m = prepare_triangle_mesh(s, options);
      expect_clean(m);
      ++accepted;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_FALSE(message.empty());
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  EXPECT_GT(accepted, 100);  // the valid-ish half must often pass
}

}  // namespace

// ---- RgbMesh::from_triangles: the library entry point makes the same checks -----------------

namespace {

using rgbmesh::PointRole;
using rgbmesh::RgbMesh;

std::vector<Triangle> triangles_of(const PolygonSoup& s) {
  std::vector<Triangle> t;
  for (const auto& f : s.faces)
    t.push_back(
        {static_cast<std::int32_t>(f[0]), static_cast<std::int32_t>(f[1]), static_cast<std::int32_t>(f[2])});
  return t;
}

// The message of the InputError thrown by from_triangles, or "" if it succeeds.
std::string library_error_of(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                             PointRole role = PointRole::surface) {
  try {
    RgbMesh::from_triangles(points, triangles, role);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Triangle soups that prepare_triangle_mesh rejects, one per check.
std::vector<std::pair<std::string, PolygonSoup>> rejected_soups() {
  std::vector<std::pair<std::string, PolygonSoup>> cases;
  PolygonSoup s = octahedron();
  s.points[4] = {std::numeric_limits<double>::quiet_NaN(), 0, 1};
  cases.emplace_back("NaN", s);
  s = octahedron();
  s.points.push_back({0, 0, std::numeric_limits<double>::infinity()});
  cases.emplace_back("inf at an unreferenced vertex", s);
  s = square();
  s.faces[1] = {0, 2, 0};
  cases.emplace_back("repeated vertex", s);
  s = square();
  s.points.push_back({2, 2, 0});
  s.faces[1] = {0, 2, 4};
  cases.emplace_back("collinear", s);
  s = square();
  s.points = {{5, 5, 5}, {5, 5, 5}, {5, 5, 5}};
  s.faces = {{0, 1, 2}};
  cases.emplace_back("coincident", s);
  s = square();
  s.points.resize(3);
  s.faces = {{0, 1, 2}, {0, 2, 1}};
  cases.emplace_back("pillow", s);
  s = octahedron();
  s.faces.push_back({4, 0, 2});
  cases.emplace_back("duplicate, rotated", s);
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {2, 3, 4}, {0, 1, 4}};
  cases.emplace_back("non-manifold edge", s);
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  cases.emplace_back("bow tie", s);
  // A Möbius strip of 6 quads.
  s = PolygonSoup();
  for (int i = 0; i < 6; ++i) {
    const double a = 2 * M_PI * i / 6, half = a / 2;
    for (const double w : {-0.3, 0.3})
      s.points.push_back({(1 + w * std::cos(half)) * std::cos(a), (1 + w * std::cos(half)) * std::sin(a),
                          w * std::sin(half)});
  }
  for (int i = 0; i < 6; ++i) {
    const std::int64_t a0 = 2 * i, a1 = 2 * i + 1, b0 = i + 1 < 6 ? 2 * (i + 1) : 1,
                       b1 = i + 1 < 6 ? 2 * (i + 1) + 1 : 0;
    s.faces.push_back({a0, b0, b1});
    s.faces.push_back({a0, b1, a1});
  }
  cases.emplace_back("Moebius strip", s);
  return cases;
}

TEST(FromTriangles, RejectsWhatTheFilePathRejectsWithTheSameMessage) {
  for (const auto& [name, soup] : rejected_soups()) {
    const std::string file_error = error_of(soup);
    ASSERT_NE(file_error, "") << name;
    EXPECT_EQ(library_error_of(soup.points, triangles_of(soup)), file_error) << name;
  }
}

TEST(FromTriangles, ThePillowOfTheIssueIsRejected) {
  // Two triangles glued back to back: it used to be accepted, and failed validate() after
  // UniformLevel(2).
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(library_error_of(points, {{0, 1, 2}, {0, 2, 1}}),
            "triangles 0 and 1 are duplicates (vertices 0, 1, 2)");
}

TEST(FromTriangles, NamesTrianglesAndTheMeshWhereTheFilePathNamesFacesAndTheFile) {
  const PolygonSoup o = octahedron();
  std::vector<Triangle> t = triangles_of(o);
  t[5] = {1, 99, 5};
  EXPECT_EQ(library_error_of(o.points, t), "triangle 5 references vertex 99 but the mesh has 6 vertices");
  t[5] = {1, -1, 5};
  EXPECT_EQ(library_error_of(o.points, t), "triangle 5 references vertex -1 but the mesh has 6 vertices");
  EXPECT_EQ(library_error_of(o.points, {}), "the mesh is empty (6 vertices, 0 triangles)");
  EXPECT_EQ(library_error_of({}, {}), "the mesh is empty (0 vertices, 0 triangles)");
}

TEST(FromTriangles, RejectsWhatTheFilePathRepairs) {
  // Inconsistent orientation: triangle 2 of the octahedron reversed. prepare_triangle_mesh
  // re-orients it; the library would have to change the caller's triangle, so it refuses.
  PolygonSoup s = octahedron();
  std::swap(s.faces[2][1], s.faces[2][2]);
  EXPECT_EQ(library_error_of(s.points, triangles_of(s)),
            "triangles 1 and 2 are oriented inconsistently across edge (1, 4) (prepare_triangle_mesh repairs "
            "this)");
  const TriangleMeshData repaired = prepare_triangle_mesh(s);
  EXPECT_EQ(library_error_of(repaired.points, repaired.triangles), "");

  // Unreferenced vertices: dropping them would renumber the caller's vertices.
  s = octahedron();
  s.points.push_back({3, 3, 3});
  EXPECT_EQ(library_error_of(s.points, triangles_of(s)),
            "vertex 6 is not referenced by any triangle (prepare_triangle_mesh repairs this)");
  EXPECT_EQ(library_error_of(prepare_triangle_mesh(s).points, prepare_triangle_mesh(s).triangles), "");
}

TEST(FromTriangles, KeepsTheCallersNumberingAndOrientation) {
  const PolygonSoup o = octahedron();
  const std::vector<Triangle> t = triangles_of(o);
  const RgbMesh m = RgbMesh::from_triangles(o.points, t);
  ASSERT_EQ(m.validate(true), "");
  ASSERT_EQ(m.num_triangles(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const auto c = m.triangle_vertices(rgbmesh::TriangleHandle(static_cast<std::int32_t>(i)));
    EXPECT_EQ((Triangle{c[0].idx, c[1].idx, c[2].idx}), t[i]);
  }
  for (std::size_t v = 0; v < o.points.size(); ++v)
    EXPECT_EQ(m.insertion_point(rgbmesh::VertexHandle(static_cast<std::int32_t>(v))), o.points[v]);
}

TEST(FromTriangles, ValuesMayBeDegenerateButNotBroken) {
  // Indicator coordinates (the probes of the limit stencils) put corners at one point.
  const PolygonSoup o = octahedron();
  std::vector<Vec3> probe(o.points.size(), Vec3(0, 0, 0));
  probe[4] = {1, 0, 0};
  EXPECT_NE(library_error_of(probe, triangles_of(o)).find("is degenerate"), std::string::npos);
  EXPECT_EQ(library_error_of(probe, triangles_of(o), PointRole::values), "");
  // Topology and finiteness are checked all the same.
  probe[1].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(library_error_of(probe, triangles_of(o), PointRole::values),
            "vertex 1 has a non-finite coordinate (0, nan, 0)");
  EXPECT_EQ(library_error_of({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, {{0, 1, 2}, {0, 2, 1}}, PointRole::values),
            "triangles 0 and 1 are duplicates (vertices 0, 1, 2)");
}

// Its time against the mesh size is a benchmark (BM_FromTriangles in bench/bench_refinement.cpp).
TEST(FromTriangles, AMillionTrianglesMakeTheirDisk) {
  PolygonSoup s = flipped_grid(1000, 500);
  for (std::size_t t = 1; t < s.faces.size(); t += 3) std::swap(s.faces[t][1], s.faces[t][2]);  // unflip
  const std::vector<Triangle> t = triangles_of(s);
  const RgbMesh m = RgbMesh::from_triangles(s.points, t);
  EXPECT_EQ(m.num_triangles(), 1000000u);
  EXPECT_EQ(m.num_vertices(), 1001u * 501u);
  EXPECT_EQ(m.euler_characteristic(), 1);  // a disk
  EXPECT_EQ(m.boundary_loops(), 1);
}

// The defects a repair fixes are MeshDefectErrors, each with what the repair does about it; a
// file's own faults are plain InputErrors.
TEST(Soup, DefectsSayWhatARepairDoes) {
  const auto hint_of = [](const PolygonSoup& soup) -> std::string {
    try {
      prepare_triangle_mesh(soup);
    } catch (const rgbmesh::MeshDefectError& e) {
      return e.hint();
    } catch (const InputError& e) {
      return std::string("not a defect: ") + e.what();
    }
    return "accepted";
  };
  PolygonSoup s = square();
  s.faces[1] = {0, 2, 0};
  EXPECT_EQ(hint_of(s), "collapses degenerate triangles");
  s = octahedron();
  s.faces.push_back({2, 0, 4});
  EXPECT_EQ(hint_of(s), "removes duplicate triangles");
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_EQ(hint_of(s), "splits non-manifold edges");
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_EQ(hint_of(s), "splits non-manifold vertices");
  s = octahedron();
  s.faces[5] = {1, 2, 99};
  EXPECT_EQ(hint_of(s), "not a defect: face 5 references vertex 99 but the file has 6 vertices");
}

// STL has no vertex numbers (its reader merges the facets' corners by position): messages name
// positions, and triangles by their number in the file.
TEST(Soup, WithoutVertexNumbersMessagesNamePositions) {
  PolygonSoup s;
  s.numbered_vertices = false;
  s.points = {{0, 0, 0}, {1.5, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0.25}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_EQ(error_of(s), "the vertex at (0, 0, 0) is non-manifold: its triangles form 2 separate fans");
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_EQ(error_of(s), "the edge from (0, 0, 0) to (1, 0, 0) is shared by 3 triangles: 0, 1, 2");
  s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  s.faces = {{0, 1, 2}};
  EXPECT_EQ(error_of(s),
            "triangle 0 is degenerate: it has zero area (its corners (0, 0, 0), (1, 0, 0), (2, 0, 0) "
            "are collinear)");
  s.faces = {{0, 1, 1}};
  EXPECT_EQ(error_of(s), "triangle 0 is degenerate: it repeats the vertex at (1, 0, 0)");
  s = octahedron();
  s.numbered_vertices = false;
  s.faces.push_back({4, 0, 2});
  EXPECT_EQ(error_of(s), "triangles 0 and 8 are duplicates (corners (1, 0, 0), (0, 1, 0), (0, 0, 1))");
  s.faces.pop_back();
  s.points[3].y = std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_of(s), "a corner of triangle 2 has a non-finite coordinate (0, inf, 0)");
  // Single-precision coordinates are written as the file has them, not as 18.732500076293945.
  s.points = {{0, 0, 0}, {static_cast<double>(18.7325f), 0, 0}, {40, 0, 0}};
  s.faces = {{0, 1, 2}};
  EXPECT_EQ(error_of(s),
            "triangle 0 is degenerate: it has zero area (its corners (0, 0, 0), (18.7325, 0, 0), (40, 0, 0) "
            "are collinear)");
}

// Faces that meet only at equal positions are separate pieces: said in a note.
TEST(Soup, DuplicatePositionsAreNoted) {
  PolygonSoup s = square();
  s.points.push_back({1, 1, 0});  // a second vertex at vertex 2's position
  s.points.push_back({0, 0, 0});  // and one at vertex 0's
  s.faces[1] = {5, 4, 3};
  const TriangleMeshData m = prepare_triangle_mesh(s);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_EQ(m.notes[0],
            "6 vertices at 4 positions: faces that meet only at equal positions are not joined (--repair "
            "merges them)");
  EXPECT_TRUE(prepare_triangle_mesh(square()).notes.empty());
}

}  // namespace
