// Meshes as tools export them (issue 23), through the tool as a user runs it: the note on
// duplicate positions, refusals that name positions and say what --repair would do, --repair on
// every subcommand that reads a mesh, and info on point clouds. The files are public (OpenSCAD's,
// geomview's, assimp's and CGAL's test data: scripts/fetch-test-data.sh); what each is known to
// be comes from the file itself (counted independently of rgbmesh: positions, triangles, how
// often each edge is used, the fans around each vertex) or from the model it was made from, as
// the comments say.

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cli_fixture.hpp"
#include "public_data.hpp"

namespace {

using namespace rgbmesh::testing;

// A mesh as the tool's OFF writer writes it.
struct OffMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<long, 3>> triangles;
};

OffMesh read_off(const std::string& file) {
  std::ifstream in(file);
  std::string magic;
  long v = 0, f = 0, e = 0;
  in >> magic >> v >> f >> e;
  OffMesh m;
  m.points.resize(static_cast<std::size_t>(v));
  for (auto& p : m.points) in >> p[0] >> p[1] >> p[2];
  for (long i = 0; i < f; ++i) {
    int n = 0;
    std::array<long, 3> t{};
    in >> n >> t[0] >> t[1] >> t[2];
    m.triangles.push_back(t);
  }
  EXPECT_TRUE(in) << file;
  return m;
}

// The enclosed volume (divergence theorem).
double volume_of(const OffMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const auto &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
  }
  return v;
}

// The boundary loops: chains of edges that one triangle uses, as vertex lists.
std::vector<std::vector<long>> boundary_loops(const OffMesh& m) {
  std::map<std::pair<long, long>, int> uses;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::map<long, std::vector<long>> next;
  for (const auto& [e, n] : uses)
    if (n == 1) {
      next[e.first].push_back(e.second);
      next[e.second].push_back(e.first);
    }
  std::set<long> seen;
  std::vector<std::vector<long>> loops;
  for (const auto& [start, around] : next) {
    if (seen.count(start)) continue;
    std::vector<long> loop;
    for (long v = start, from = -1; !seen.count(v);) {
      seen.insert(v);
      loop.push_back(v);
      const long to = next[v][0] != from ? next[v][0] : next[v][1];
      from = v;
      v = to;
    }
    loops.push_back(loop);
  }
  return loops;
}

long json_value(const std::string& json, const std::string& key) {
  const auto p = json.find("\"" + key + "\": ");
  if (p == std::string::npos) return -999999;
  return std::stol(json.substr(p + key.size() + 4));
}

// `info --json` of a file: the counts, with the notes on standard error.
struct Info {
  int code = -1;
  std::string json, err;
  long operator[](const std::string& key) const { return json_value(json, key); }
};

class CliRepair : public Cli {
 protected:
  Info info(const std::string& args) const {
    const RunResult r = run("info --json " + args);
    return {r.code, r.out, r.err};
  }
  // A refusal: exit code 2 and one line.
  void expect_refused(const RunResult& r, const std::string& what) const {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
};

TEST_F(CliRepair, TrefoilFacesAreJoinedByRepair) {
  // geomview's tref.off: a tube around a trefoil knot as 320 quads, each with its own 4 vertices
  // (1,280) at 328 distinct positions: 40 rings of 8 around the tube and a 41st ring that closes
  // it, 8 positions turned against the first ring's (the tube's frame turns along the knot).
  const std::string tref = public_data("geomview/tref.off");
  const Info plain = info("--triangulate " + tref);
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.err.find(
                "1,280 vertices at 328 positions: faces that meet only at equal positions are not joined "
                "(--repair merges them)"),
            std::string::npos)
      << plain.err;
  EXPECT_EQ(plain["components"], 320);

  const Info fixed = info("--triangulate --repair " + tref);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_NE(fixed.err.find("repaired: merged 952 duplicate vertices"), std::string::npos) << fixed.err;
  EXPECT_EQ(fixed["vertices"], 328);
  EXPECT_EQ(fixed["triangles"], 640);
  EXPECT_EQ(fixed["components"], 1);
  EXPECT_EQ(fixed["euler_characteristic"], 0);
  // The tube's two end rings share no vertex: a torus as a shape, an open tube as a mesh (genus 0,
  // two boundary loops). Both loops lie on one circle: the seam where the file's tube closes.
  EXPECT_EQ(fixed["boundary_loops"], 2);
  EXPECT_EQ(fixed["genus"], 0);
  ASSERT_EQ(run("convert --triangulate --repair " + tref + " " + path("tref.off")).code, 0);
  const OffMesh m = read_off(path("tref.off"));
  const auto loops = boundary_loops(m);
  ASSERT_EQ(loops.size(), 2u);
  std::array<std::array<double, 3>, 2> centre{};
  std::array<double, 2> radius{};
  for (int l = 0; l < 2; ++l) {
    ASSERT_EQ(loops[l].size(), 8u);
    for (const long v : loops[l])
      for (int k = 0; k < 3; ++k) centre[l][k] += m.points[v][k] / 8;
    for (const long v : loops[l])
      radius[l] += std::hypot(m.points[v][0] - centre[l][0], m.points[v][1] - centre[l][1],
                              m.points[v][2] - centre[l][2]) /
                   8;
  }
  EXPECT_LT(std::hypot(centre[0][0] - centre[1][0], centre[0][1] - centre[1][1], centre[0][2] - centre[1][2]),
            1e-3);
  EXPECT_NEAR(radius[0], radius[1], 1e-3);
}

TEST_F(CliRepair, ZeroAreaTriangleOfOpenScad) {
  // OpenSCAD's issue1580-zero-area-triangle.stl, from a polyhedron (its .scad): the cube
  // [0, 10]^3 with a ninth vertex (0, 0, 5) on the edge from (0, 0, 0) to (0, 0, 10), and the
  // triangle of those three collinear points among its 14.
  const std::string stl = public_data("openscad/issue1580-zero-area-triangle.stl");
  for (const std::string& args :
       {"info " + stl, "refine " + stl + " - --uniform 1", "convert " + stl + " " + path("x.vtp")}) {
    const RunResult r = run(args);
    expect_refused(
        r,
        "is degenerate: it has zero area (its corners (0, 0, 0), (0, 0, 5), (0, 0, 10) are collinear) "
        "(--repair collapses degenerate triangles)");
    EXPECT_EQ(r.err.find("vertices "), std::string::npos) << "an STL file has no vertex numbers: " << r.err;
  }
  expect_refused(run("adapt --mesh " + stl + " --out " + path("a")),
                 "(--repair collapses degenerate triangles)");

  const Info fixed = info("--repair " + stl);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_NE(fixed.err.find("repaired: collapsed 1 zero-area triangle"), std::string::npos) << fixed.err;
  EXPECT_EQ(fixed["vertices"], 9);
  EXPECT_EQ(fixed["triangles"], 14);
  EXPECT_EQ(fixed["boundary_loops"], 0);
  EXPECT_EQ(fixed["components"], 1);
  EXPECT_EQ(fixed["genus"], 0);
  ASSERT_EQ(run("convert --repair " + stl + " " + path("cube.off")).code, 0);
  EXPECT_NEAR(std::abs(volume_of(read_off(path("cube.off")))), 1000, 1e-9);

  // What reads a mesh works on the repaired one.
  const RunResult refined = run("refine --repair " + stl + " " + path("r.vtp") + " --uniform 2");
  ASSERT_EQ(refined.code, 0) << refined.err;
  EXPECT_EQ(info(path("r.vtp"))["triangles"], 14 * 16);
  const RunResult adapted = run("adapt --repair --mesh " + stl + " --cycles 2 --out " + path("a"));
  EXPECT_EQ(adapted.code, 0) << adapted.err;
  EXPECT_NE(adapted.err.find("repaired: collapsed 1 zero-area triangle"), std::string::npos) << adapted.err;
}

TEST_F(CliRepair, BackToBackZeroAreaPairOfOpenScad) {
  // issue1580-back-to-back.stl (its .scad): the tetrahedra (0,4,0) (0,0,0) (0,2,-4) (+-2,2,0) on
  // either side of x = 0, each of volume 16/3, glued along a zero-area triangle written twice.
  const std::string stl = public_data("openscad/issue1580-back-to-back.stl");
  expect_refused(run("info " + stl), "(--repair collapses degenerate triangles)");
  const Info fixed = info("--repair " + stl);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_EQ(fixed["vertices"], 6);
  EXPECT_EQ(fixed["triangles"], 8);
  EXPECT_EQ(fixed["boundary_loops"], 0);
  EXPECT_EQ(fixed["euler_characteristic"], 2);
  ASSERT_EQ(run("convert --repair " + stl + " " + path("b.off")).code, 0);
  EXPECT_NEAR(std::abs(volume_of(read_off(path("b.off")))), 32.0 / 3, 1e-9);
}

TEST_F(CliRepair, PigPatchesMeetingAtVertices) {
  // CGAL's pig.stl: 16,848 triangles at 8,642 positions, 17 patches (edge-connected pieces)
  // with 1,296 boundary edges; 421 positions are non-manifold vertices whose triangles form 864
  // fans in all. Split into their fans: 9,085 vertices, 17 components, 21 boundary loops.
  const std::string pig = public_data("pig.stl");
  const RunResult r = run("info " + pig);
  expect_refused(
      r, "is non-manifold: its triangles form 2 separate fans (--repair splits non-manifold vertices)");
  EXPECT_EQ(r.err.find(": vertex "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the vertex at ("), std::string::npos) << r.err;

  const Info fixed = info("--repair " + pig);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_NE(fixed.err.find("repaired: split 421 non-manifold vertices into 864"), std::string::npos)
      << fixed.err;
  EXPECT_EQ(fixed["vertices"], 9085);
  EXPECT_EQ(fixed["triangles"], 16848);
  EXPECT_EQ(fixed["components"], 17);
  EXPECT_EQ(fixed["boundary_loops"], 21);
  EXPECT_EQ(fixed["euler_characteristic"], 13);
  const RunResult adapted = run("adapt --repair --mesh " + pig + " --cycles 2 --out " + path("a"));
  EXPECT_EQ(adapted.code, 0) << adapted.err;
}

TEST_F(CliRepair, OpenScadCircuitBoard) {
  // adns2610_dev_circuit_inv.stl: 900 triangles at 424 positions, every edge used twice, one
  // piece, Euler characteristic -26: a closed surface of genus 14; among its triangles, zero-area
  // ones.
  const std::string stl = public_data("openscad/adns2610_dev_circuit_inv.stl");
  expect_refused(run("info " + stl), "(--repair collapses degenerate triangles)");
  const Info fixed = info("--repair " + stl);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_NE(fixed.err.find("repaired: collapsed 2 zero-area triangles"), std::string::npos) << fixed.err;
  EXPECT_EQ(fixed["components"], 1);
  EXPECT_EQ(fixed["boundary_loops"], 0);
  EXPECT_EQ(fixed["euler_characteristic"], -26);
  EXPECT_EQ(fixed["genus"], 14);
}

TEST_F(CliRepair, FilesThatOnceBrokeOpenScadStayWhatTheyAre) {
  // The bad-stl-*.stl files are valid closed surfaces (V, E, F counted from the files): --repair
  // may flip caps but changes no count.
  struct Case {
    const char* file;
    long vertices, edges, triangles, genus;
  } cases[] = {{"openscad/bad-stl-pcbvicebar.stl", 132, 390, 260, 0},
               {"openscad/bad-stl-tardis.stl", 1796, 5454, 3636, 12},
               {"openscad/bad-stl-wing.stl", 423, 1263, 842, 0},
               {"openscad/import.stl", 25, 69, 46, 0}};
  for (const Case& c : cases) {
    for (const char* repair : {"", "--repair "}) {
      const Info i = info(repair + public_data(c.file));
      ASSERT_EQ(i.code, 0) << c.file << " " << i.err;
      EXPECT_EQ(i["vertices"], c.vertices) << c.file << " " << repair;
      EXPECT_EQ(i["edges"], c.edges) << c.file << " " << repair;
      EXPECT_EQ(i["triangles"], c.triangles) << c.file << " " << repair;
      EXPECT_EQ(i["genus"], c.genus) << c.file << " " << repair;
      EXPECT_EQ(i["boundary_loops"], 0) << c.file << " " << repair;
    }
  }
}

TEST_F(CliRepair, SliversOfCoordinatesThatAreZeroButForRounding) {
  // issue945e.stl: points meant on the edge x = 0, y = 1.5 written with x = 1e-16 ... 1e-15, and
  // slivers between them; 94 triangles at 49 positions, closed, Euler characteristic 2.
  const std::string stl = public_data("openscad/issue945e.stl");
  expect_refused(run("info " + stl), "(--repair collapses degenerate triangles)");
  const Info fixed = info("--repair " + stl);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_EQ(fixed["boundary_loops"], 0);
  EXPECT_EQ(fixed["euler_characteristic"], 2);
  EXPECT_NE(fixed.err.find("to 0"), std::string::npos) << fixed.err;
}

TEST_F(CliRepair, AssimpModels) {
  // sphereWithHole.stl: 285 triangles at 146 positions, 9 boundary edges, 2 non-manifold
  // vertices of 2 fans each: split, a disk (Euler characteristic 1) with one boundary loop.
  const std::string sphere = public_data("assimp/sphereWithHole.stl");
  expect_refused(run("info " + sphere), "(--repair splits non-manifold vertices)");
  Info i = info("--repair " + sphere);
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["vertices"], 148);
  EXPECT_EQ(i["components"], 1);
  EXPECT_EQ(i["boundary_loops"], 1);
  EXPECT_EQ(i["euler_characteristic"], 1);

  // 3DSMaxExport.STL: 2,000 triangles at 1,042 positions, 16 edges of 3 triangles each, whose
  // 16 end points have 48 fans: split, 1,074 vertices.
  const std::string max = public_data("assimp/3DSMaxExport.STL");
  expect_refused(run("info " + max), "is shared by 3 triangles: ");
  EXPECT_NE(run("info " + max).err.find("the edge from ("), std::string::npos);
  EXPECT_NE(run("info " + max).err.find("(--repair splits non-manifold edges)"), std::string::npos);
  i = info("--repair " + max);
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["vertices"], 1074);
  EXPECT_EQ(i["triangles"], 2000);
  EXPECT_NE(i.err.find("split 16 non-manifold edges"), std::string::npos) << i.err;

  // Spider_binary.stl: 1,368 triangles at 722 positions, 56 of them with two corners at one
  // position.
  const std::string spider = public_data("assimp/Spider_binary.stl");
  expect_refused(run("info " + spider), "is degenerate: it repeats the vertex at (");
  i = info("--repair " + spider);
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["vertices"], 722);
  EXPECT_EQ(i["triangles"], 1368 - 56);

  // cube_uv.ply: a cube written as 6 squares with their own vertices (24 at 8 positions).
  const std::string cube = public_data("assimp/cube_uv.ply");
  i = info("--triangulate " + cube);
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["components"], 6);
  EXPECT_NE(i.err.find("24 vertices at 8 positions"), std::string::npos) << i.err;
  i = info("--triangulate --repair " + cube);
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["vertices"], 8);
  EXPECT_EQ(i["components"], 1);
  EXPECT_EQ(i["boundary_loops"], 0);
  EXPECT_EQ(i["euler_characteristic"], 2);
  // Polygons still need --triangulate, and the message says so.
  expect_refused(run("info --repair " + cube),
                 "(use --triangulate to split polygons; a repair needs it too)");

  // Wuson.off: numbered vertices keep their numbers in messages; --repair makes it valid.
  const std::string wuson = public_data("assimp/Wuson.off");
  expect_refused(run("info " + wuson), ": vertex 170 is non-manifold");
  EXPECT_EQ(info("--repair " + wuson).code, 0);
}

TEST_F(CliRepair, GeomviewModels) {
  // cam.off: two triangles sharing one vertex only.
  const Info cam = info("--repair " + public_data("geomview/cam.off"));
  ASSERT_EQ(cam.code, 0) << cam.err;
  EXPECT_EQ(cam["components"], 2);
  EXPECT_NE(cam.err.find("split 1 non-manifold vertex into 2"), std::string::npos) << cam.err;
  // br2.off: pentagons with corners in line, whose fan-split gave zero-area triangles; cut
  // into ears, they are a closed surface as they are.
  const std::string br2 = public_data("geomview/br2.off");
  const Info plain = info("--triangulate " + br2);
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain["triangles"], 36);
  EXPECT_EQ(plain["euler_characteristic"], 2);
  const Info fixed = info("--triangulate --repair " + br2);
  ASSERT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_EQ(fixed["boundary_loops"], 0);
  EXPECT_EQ(fixed["euler_characteristic"], 2);
}

// The polygons of an OFF file, as corner lists.
std::vector<std::vector<std::array<double, 3>>> off_polygons(const std::string& file) {
  std::ifstream in(file);
  std::string line, magic;
  const auto next_line = [&]() {
    while (std::getline(in, line))
      if (line.find_first_not_of(" \t\r") != std::string::npos && line[line.find_first_not_of(" \t")] != '#') return true;
    return false;
  };
  next_line();
  std::istringstream head(line);
  head >> magic;
  long v = 0, f = 0;
  if (!(head >> v >> f)) {
    next_line();
    std::istringstream counts(line);
    counts >> v >> f;
  }
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(v));
  for (auto& p : points) {
    next_line();
    std::istringstream(line) >> p[0] >> p[1] >> p[2];
  }
  std::vector<std::vector<std::array<double, 3>>> polygons;
  for (long i = 0; i < f && next_line(); ++i) {
    std::istringstream face(line);
    long n = 0, k = 0;
    face >> n;
    polygons.emplace_back();
    for (long j = 0; j < n && face >> k; ++j) polygons.back().push_back(points[static_cast<std::size_t>(k)]);
  }
  return polygons;
}

// The area of a polygon: half the length of Newell's area vector.
double polygon_area(const std::vector<std::array<double, 3>>& p) {
  double a[3] = {0, 0, 0};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto &u = p[i], &w = p[(i + 1) % p.size()];
    a[0] += u[1] * w[2] - u[2] * w[1];
    a[1] += u[2] * w[0] - u[0] * w[2];
    a[2] += u[0] * w[1] - u[1] * w[0];
  }
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) / 2;
}

TEST_F(CliRepair, ConcavePolygonsOfRealModelsAreSplitWithoutOverlaps) {
  // CGAL's polygon models (concave hexagons and 10-gons, corners in line) and geomview's
  // br2.off: the triangles' areas add up to the polygons' (a fan over a concave polygon folds
  // triangles over each other, whose areas then add up to more), one triangle fewer than
  // corners per polygon, less two.
  for (const std::string name : {"mpi.off", "P.off", "corner_poly.off", "double-torus-3-holes.off", "geomview/br2.off"}) {
    const std::string file = public_data(name), out = path("split.off");
    const RunResult r = run("convert --triangulate " + file + " " + out);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_NE(r.err.find("by cutting ears in their planes"), std::string::npos) << name << ": " << r.err;
    const auto polygons = off_polygons(file);
    double expected = 0;
    std::size_t triangles = 0;
    for (const auto& p : polygons) expected += polygon_area(p), triangles += p.size() - 2;
    const OffMesh m = read_off(out);
    EXPECT_EQ(m.triangles.size(), triangles) << name;
    double area = 0;
    for (const auto& t : m.triangles) area += polygon_area({m.points[t[0]], m.points[t[1]], m.points[t[2]]});
    EXPECT_NEAR(area, expected, 1e-6 * expected) << name;
  }
}

TEST_F(CliRepair, InfoOnPointClouds) {
  RunResult r = run("info " + public_data("kitten.xyz"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind(public_data("kitten.xyz") +
                            ": a point cloud of 5,210 points (with normals), no faces: "
                            "rgbmesh fit --target " +
                            public_data("kitten.xyz") + " fits a surface to it\n",
                        0),
            0u)
      << r.out;
  const Info hippo = info(public_data("hippo1.ply"));  // a binary PLY with vertices only
  ASSERT_EQ(hippo.code, 0) << hippo.err;
  EXPECT_NE(hippo.json.find("\"point_cloud\": true"), std::string::npos) << hippo.json;
  EXPECT_EQ(hippo["points"], 6104);
  EXPECT_EQ(hippo["triangles"], 0);
  r = run("info " + public_data("assimp/point_cloud.obj"));  // 3 'v' lines, nothing else
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("a point cloud of 3 points (without normals)"), std::string::npos) << r.out;
  r = run("info " + public_data("assimp/points.ply"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("a point cloud of 4 points"), std::string::npos) << r.out;
  // The tool's own point clouds: fit's targets.vtp (vertex cells only; written also when so
  // coarse a fit fails its two-sided check, exit code 2).
  const int fitted = run("fit --target " + public_data("oni.pwn") + " --base-faces 100 --levels 1 --iterations 1 --out " +
                         path("fit"))
                         .code;
  ASSERT_TRUE(fitted == 0 || fitted == 2) << fitted;
  const Info targets = info(path("fit/targets.vtp"));
  ASSERT_EQ(targets.code, 0) << targets.err;
  EXPECT_EQ(targets["points"], 1435);
  // A bad cloud is still a one-line error.
  std::ofstream(path("bad.xyz")) << "1 2 3\n4 5 x\n";
  expect_refused(run("info " + path("bad.xyz")), "bad.xyz");
}

TEST_F(CliRepair, FitRepairsTheTargetFacesAndTheBase) {
  const std::string stl = public_data("openscad/issue1580-zero-area-triangle.stl");
  const std::string common = " --levels 1 --iterations 2 --out " + path("fit");
  expect_refused(run("fit --target " + stl + " --base " + stl + common),
                 "(--repair collapses degenerate triangles)");
  // Repaired, the fit runs; so coarse a fit (level 1, the 14-triangle target as its own base)
  // may then fail the two-sided check, exit code 2 with the figures.
  const auto fitted = [](const RunResult& run) {
    return run.code == 0 || (run.code == 2 && run.err.find("of the diagonal") != std::string::npos);
  };
  RunResult r = run("fit --repair --target " + stl + " --base " + stl + common);
  EXPECT_TRUE(fitted(r)) << r.err;
  EXPECT_NE(r.err.find("repaired: collapsed 1 zero-area triangle"), std::string::npos) << r.err;
  // The target's faces: without --repair they are not a surface, and the fit is refused with
  // what a repair would do (a reconstruction from the vertices would drop what the faces say);
  // with it they are, and the base is the target's own faces.
  const std::string pig = public_data("pig.stl");
  expect_refused(run("fit --target " + pig + " --base-faces 300" + common), "(--repair splits");
  r = run("fit --repair --target " + pig + " --base-faces 300" + common);
  EXPECT_TRUE(fitted(r)) << r.err;
  EXPECT_NE(r.out.find("base (decimated)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("17 components, genus 0, 21 boundary loops"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(pig + ": repaired: split 421 non-manifold vertices into 864"), std::string::npos)
      << r.err;
}

TEST_F(CliRepair, AFileWithAnRgbStateIsRestoredNotRepaired) {
  const std::string in = write_octahedron("octa.off");
  ASSERT_EQ(run("refine " + in + " " + path("r.vtp") + " --uniform 2").code, 0);
  const Info i = info("--repair " + path("r.vtp"));
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_EQ(i["max_level"], 2);
  EXPECT_NE(i.err.find("r.vtp: the file has an RGB state: restored exactly, not repaired"), std::string::npos)
      << i.err;
  // A resumed run's mesh is its last cycle's: --repair is refused.
  ASSERT_EQ(run("adapt --cycles 2 --out " + path("run")).code, 0);
  expect_refused(run("adapt --resume " + path("run") + " --cycles 3 --repair"),
                 "--repair: does not apply with --resume");
}

TEST_F(CliRepair, EveryReadingSubcommandHasRepair) {
  for (const std::string sub : {"info", "convert", "refine", "adapt", "fit"})
    EXPECT_NE(run(sub + " --help").out.find("--repair"), std::string::npos) << sub;
}

}  // namespace
