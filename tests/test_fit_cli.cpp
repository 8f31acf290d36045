// `rgbmesh fit` as a user runs it: point clouds and meshes that failed before (issue 9), the
// files it writes (targets.vtp's distances are the report's figures; limit_surface.vtp's cell
// data), the report's stages, one-line errors with exit code 2, and the output-folder rule.

#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "cli_fixture.hpp"
#include "public_data.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::testing {
namespace {

// Reproducible numbers in [0, 1) (a 64-bit linear congruential generator): the same clouds on
// every machine and library version.
struct UniformNumbers {
  explicit UniformNumbers(std::uint64_t seed) : state(seed) {}
  double operator()() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  }
  std::uint64_t state;
};

// The number after "key": in a JSON text (the first occurrence after `from`).
double json_number(const std::string& json, const std::string& key, std::size_t from = 0) {
  const auto p = json.find("\"" + key + "\": ", from);
  EXPECT_NE(p, std::string::npos) << key << " in " << json;
  return p == std::string::npos ? NAN : std::stod(json.substr(p + key.size() + 4));
}

class FitCli : public Cli {
 protected:
  // Fibonacci points on a sphere of radius 2 as "x y z" lines: a cloud without normals.
  std::string write_sphere_cloud(const std::string& name, int n) const {
    std::ofstream f(path(name));
    f.precision(17);
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
      f << 2 * r * std::cos(golden * i) << " " << 2 * r * std::sin(golden * i) << " " << 2 * z << "\n";
    }
    return path(name);
  }
};

TEST_F(FitCli, PointCloudTargetsVtpHoldsTheReportedDistances) {
  const std::string cloud = write_sphere_cloud("sphere.xyz", 2000);
  const RunResult r = run("fit --target " + cloud + " --out " + path("f") + " --report " + path("f.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* file :
       {"base.obj", "fitted_base.obj", "limit_surface.vtp", "initial_limit_surface.vtp", "targets.vtp"})
    EXPECT_TRUE(fs::exists(path("f") + "/" + file)) << file;

  const vtkSmartPointer<vtkPolyData> targets = read_vtp(path("f/targets.vtp"));
  ASSERT_EQ(targets->GetNumberOfPoints(), 2000);
  EXPECT_EQ(targets->GetNumberOfVerts(), 2000);
  vtkDataArray* distance = targets->GetPointData()->GetArray("distance");
  ASSERT_NE(distance, nullptr);
  double sum = 0, max = 0;
  for (vtkIdType i = 0; i < distance->GetNumberOfTuples(); ++i) {
    const double d = distance->GetComponent(i, 0);
    sum += d * d;
    max = std::max(max, d);
  }
  const std::string report = read_text(path("f.json"));
  const std::size_t top = report.find("\"iterations\": [");
  const std::size_t after_iterations = report.find("]", top);
  EXPECT_DOUBLE_EQ(std::sqrt(sum / 2000), json_number(report, "rms", after_iterations));
  EXPECT_DOUBLE_EQ(max, json_number(report, "max", after_iterations));
  const double diagonal = json_number(report, "diagonal", after_iterations);
  EXPECT_NEAR(diagonal, 4 * std::sqrt(3.0), 0.01);
  EXPECT_LT(std::sqrt(sum / 2000), 1e-3 * diagonal);

  // The stages.
  EXPECT_NE(report.find("\"source\": \"reconstructed\""), std::string::npos) << report;
  EXPECT_EQ(json_number(report, "faces", report.find("\"base\"")), 1000);
  EXPECT_EQ(json_number(report, "genus", report.find("\"base\"")), 0);
  EXPECT_GT(json_number(report, "reconstruction_seconds"), 0);
  EXPECT_GT(json_number(report, "decimation_seconds"), 0);
  EXPECT_NE(report.find("\"notes\": [\"reconstructed a surface of "), std::string::npos) << report;
  EXPECT_NE(report.find("\"normals\": false"), std::string::npos) << report;

  // The limit surface: per triangle, the targets whose closest point is in it and their RMS
  // distance; no per-vertex "distance" (it was to the nearest target, the sample spacing).
  const vtkSmartPointer<vtkPolyData> limit = read_vtp(path("f/limit_surface.vtp"));
  EXPECT_EQ(limit->GetNumberOfPolys(), 1000 * 64);
  EXPECT_EQ(limit->GetPointData()->GetArray("distance"), nullptr);
  vtkDataArray* counts = limit->GetCellData()->GetArray("targets");
  vtkDataArray* rms = limit->GetCellData()->GetArray("rms_distance");
  ASSERT_NE(counts, nullptr);
  ASSERT_NE(rms, nullptr);
  double counted = 0, squares = 0;
  for (vtkIdType t = 0; t < counts->GetNumberOfTuples(); ++t) {
    counted += counts->GetComponent(t, 0);
    squares += counts->GetComponent(t, 0) * rms->GetComponent(t, 0) * rms->GetComponent(t, 0);
  }
  EXPECT_EQ(counted, 2000);
  EXPECT_NEAR(squares, sum, 1e-9 * sum);
}

TEST_F(FitCli, TheMeshesOfTheIssueFitWithDefaultOptions) {
  // Before: "edge (32, 33) is shared by 4 triangles" (VTK's decimation of the cow) and "vertex
  // 191 is non-manifold" (of the elephant with holes).
  for (const std::string file : {"cow.off", "elephant-with-holes.off"}) {
    const RunResult r = run("fit --target " + public_data(file) + " --out " + path(file) + " --report " +
                            path(file + ".json"));
    ASSERT_EQ(r.code, 0) << file << ": " << r.err;
    const std::string report = read_text(path(file + ".json"));
    EXPECT_NE(report.find("\"source\": \"decimated\""), std::string::npos) << report;
    EXPECT_EQ(json_number(report, "faces", report.find("\"base\"")), 1000) << file;
    EXPECT_LT(json_number(report, "rms_relative"), 0.003) << file;
    const auto base = rgbmesh::read_mesh(path(file) + "/base.obj");
    EXPECT_EQ(base.triangles.size(), 1000u);
  }
}

TEST_F(FitCli, MalformedCloudsAreOneLineErrorsWithExitCode2) {
  std::ofstream(path("bad.xyz")) << "0 0 0\n1 2 x\n";
  std::ofstream(path("empty.xyz")) << "";
  std::ofstream(path("garbage.vtp"))
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><PolyData><Piece Num";
  const std::pair<std::string, std::string> cases[] = {{"bad.xyz", "bad.xyz:2: 'x' is not a number"},
                                                       {"empty.xyz", "empty.xyz: no points"},
                                                       {"garbage.vtp", "garbage.vtp: cannot read: "},
                                                       {"none.xyz", "none.xyz: file does not exist"}};
  for (const auto& [file, message] : cases) {
    const RunResult r = run("fit --target " + path(file) + " --out " + path("g"));
    EXPECT_EQ(r.code, 2) << file << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << file << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << file << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("g"))) << file;  // nothing written before the input is read
  }
}

TEST_F(FitCli, ARunRemovesThePreviousRunsOutputsOnly) {
  fs::create_directories(path("f"));
  std::ofstream(path("f/cycle_003.vtp")) << "old";
  std::ofstream(path("f/mine.txt")) << "keep";
  const RunResult r = run("fit --target " + std::string(RGBMESH_DATA_DIR) +
                          "/bunny.obj --base-faces 400 --levels 2 "
                          "--out " +
                          path("f"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(path("f/cycle_003.vtp")));
  EXPECT_TRUE(fs::exists(path("f/mine.txt")));
  EXPECT_TRUE(fs::exists(path("f/targets.vtp")));
}

// An OFF file of the unit cube's 12 triangles (outward), and of a tetrahedron inside it.
void write_cube_and_tetrahedron(const std::string& cube, const std::string& tetrahedron) {
  std::ofstream c(cube);
  c << "OFF\n8 12 0\n";
  for (int i = 0; i < 8; ++i) c << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
  for (const char* f : {"0 2 1", "1 2 3", "4 5 6", "5 7 6", "0 1 4", "1 5 4", "2 6 3", "3 6 7", "0 4 2", "2 4 6",
                        "1 3 5", "3 7 5"})
    c << "3 " << f << "\n";
  std::ofstream t(tetrahedron);
  t << "OFF\n4 4 0\n0.4 0.4 0.4\n0.6 0.4 0.4\n0.4 0.6 0.4\n0.4 0.4 0.6\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
}

TEST_F(FitCli, BothDirectionsAreReportedAndFiled) {
  const std::string cloud = write_sphere_cloud("sphere.xyz", 2000);
  const RunResult r = run("fit --target " + cloud + " --out " + path("f") + " --report " + path("f.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("targets to surface: rms "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("surface to target:  rms "), std::string::npos) << r.out;
  const std::string report = read_text(path("f.json"));
  EXPECT_NE(report.find("\"status\": \"accepted\""), std::string::npos) << report;
  // limit_surface.vtp's distance_to_target gives the report's figures: the largest, and the RMS
  // weighted by the vertices' areas (a third of their triangles').
  const vtkSmartPointer<vtkPolyData> limit = read_vtp(path("f/limit_surface.vtp"));
  vtkDataArray* d = limit->GetPointData()->GetArray("distance_to_target");
  ASSERT_NE(d, nullptr);
  std::vector<double> area(static_cast<std::size_t>(limit->GetNumberOfPoints()), 0.0);
  for (vtkIdType t = 0; t < limit->GetNumberOfCells(); ++t) {
    double p[3][3];
    vtkCell* cell = limit->GetCell(t);
    for (int k = 0; k < 3; ++k) limit->GetPoint(cell->GetPointId(k), p[k]);
    const Vec3 a(p[0][0], p[0][1], p[0][2]), b(p[1][0], p[1][1], p[1][2]), c(p[2][0], p[2][1], p[2][2]);
    for (int k = 0; k < 3; ++k) area[static_cast<std::size_t>(cell->GetPointId(k))] += norm(cross(b - a, c - a)) / 6;
  }
  double sum = 0, total = 0, max = 0;
  for (vtkIdType v = 0; v < d->GetNumberOfTuples(); ++v) {
    sum += area[static_cast<std::size_t>(v)] * d->GetComponent(v, 0) * d->GetComponent(v, 0);
    total += area[static_cast<std::size_t>(v)];
    max = std::max(max, d->GetComponent(v, 0));
  }
  const std::size_t back = report.find("\"surface_to_target\"");
  ASSERT_NE(back, std::string::npos) << report;
  EXPECT_NEAR(std::sqrt(sum / total), json_number(report, "rms", back), 1e-6 * json_number(report, "rms", back));
  EXPECT_DOUBLE_EQ(max, json_number(report, "max", back));
  // The cloud is on a sphere of radius 2: both directions are small, and honest: the surface's
  // distances to the cloud are those to the sphere, to the sampling's resolution.
  EXPECT_LT(json_number(report, "rms_relative", back), 0.002);
  const vtkSmartPointer<vtkPolyData> surface = read_vtp(path("f/limit_surface.vtp"));
  for (vtkIdType v = 0; v < surface->GetNumberOfPoints(); v += 97) {
    double p[3];
    surface->GetPoint(v, p);
    EXPECT_NEAR(d->GetComponent(v, 0), std::abs(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 2), 0.01);
  }
}

TEST_F(FitCli, ASurfaceFarFromItsTargetIsRejectedAfterItsFilesAreWritten) {
  // A tetrahedron's control net cannot make a cube: the limit surface is far from the cube's
  // faces however the points move.
  write_cube_and_tetrahedron(path("cube.off"), path("tet.off"));
  const RunResult r = run("fit --target " + path("cube.off") + " --base " + path("tet.off") + " --out " +
                          path("f") + " --report " + path("f.json"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("rgbmesh: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("% of the diagonal"), std::string::npos) << r.err;  // the figures
  EXPECT_NE(r.err.find("limit_surface.vtp shows where"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const char* file : {"limit_surface.vtp", "targets.vtp", "fitted_base.obj"})
    EXPECT_TRUE(fs::exists(path("f") + "/" + file)) << file;
  const std::string report = read_text(path("f.json"));
  EXPECT_NE(report.find("\"status\": \"rejected\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"kind\": \"surface\""), std::string::npos) << report;
}

TEST_F(FitCli, ACoarseCadMeshIsFittedAsItsSurface) {
  write_cube_and_tetrahedron(path("cube.off"), path("tet.off"));
  const RunResult r = run("fit --target " + path("cube.off") + " --iterations 10 --out " + path("f") +
                          " --report " + path("f.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string report = read_text(path("f.json"));
  EXPECT_NE(report.find("\"kind\": \"surface\""), std::string::npos) << report;
  EXPECT_GT(json_number(report, "fitted_points"), 10000);  // not its 8 vertices alone
  EXPECT_LT(json_number(report, "max_relative", report.find("\"surface_to_target\"")), 0.03);
  EXPECT_NE(r.err.find("the target has 12 faces, fewer than the 1,000 asked for"), std::string::npos) << r.err;
}

TEST_F(FitCli, SharpAngleKeepsACadPartsEdgesWithFewerBaseFaces) {
  // Netgen's hinge: a 200-face base with its creases fits within the acceptance (0.23% and 1.2%
  // of the diagonal measured); without them even 600 faces leave the rounded edges 4% away.
  const std::string hinge = public_data("netgen/hinge.stl");
  const RunResult sharp = run("fit --target " + hinge + " --base-faces 200 --sharp-angle 30 --out " + path("s") +
                              " --report " + path("s.json"));
  ASSERT_EQ(sharp.code, 0) << sharp.err;
  const std::string report = read_text(path("s.json"));
  EXPECT_LT(json_number(report, "max_relative", report.find("\"surface_to_target\"")), 0.03) << report;
  EXPECT_NE(read_text(path("s/fitted_base.obj")).find("t crease 2/1/0 "), std::string::npos);
  const RunResult smooth = run("fit --target " + hinge + " --base-faces 600 --no-retry --out " + path("r"));
  EXPECT_EQ(smooth.code, 2) << smooth.err;
  EXPECT_NE(smooth.err.find("far from the target"), std::string::npos) << smooth.err;
}

TEST_F(FitCli, ARejectedFitTriesAFinerBaseAndKeepsTheBest) {
  // The hinge with its creases on a 100-face base misses the acceptance; the second attempt,
  // 200 faces, passes (0.19% / 1.1% and 0.25% / 2.2% measured), and is what is written.
  const std::string hinge = public_data("netgen/hinge.stl");
  const RunResult r = run("fit --target " + hinge + " --base-faces 100 --sharp-angle 30 --out " + path("h") +
                          " --report " + path("h.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("attempt 1 of 4: base of 100 faces, level 3: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(": rejected\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("attempt 2 of 4: base of 200 faces, level 3: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("attempt 3 of 4"), std::string::npos) << r.out;  // stopped once accepted
  const std::string report = read_text(path("h.json"));
  EXPECT_NE(report.find("\"status\": \"accepted\""), std::string::npos) << report;
  EXPECT_EQ(json_number(report, "requested_faces"), 200);
  EXPECT_EQ(json_number(report, "base_faces", report.find("\"attempts\"")), 100);
  EXPECT_EQ(json_number(report, "base_faces", report.find("}, {", report.find("\"attempts\""))), 200);
  const auto fitted = rgbmesh::read_mesh(path("h/fitted_base.obj"));
  EXPECT_GT(fitted.triangles.size(), 150u);
  // --no-retry: today's single fit, rejected.
  const RunResult once = run("fit --target " + hinge + " --base-faces 100 --sharp-angle 30 --no-retry --out " + path("n"));
  EXPECT_EQ(once.code, 2) << once.err;
  EXPECT_EQ(once.out.find("attempt"), std::string::npos) << once.out;
  // fin90: folded and noisy, no base up to --max-base-faces fits; the rejection gives the
  // closest attempt's figures and says what was tried.
  const RunResult fin = run("fit --target " + public_data("fin90_with_PCA_normals.xyz") +
                            " --max-base-faces 2000 --out " + path("f") + " --report " + path("f.json"));
  EXPECT_EQ(fin.code, 2) << fin.err;
  EXPECT_NE(fin.out.find("attempt 3 of 4: skipped: a base of 4,000 faces is beyond --max-base-faces 2,000"),
            std::string::npos) << fin.out;
  EXPECT_NE(fin.err.find("2 attempts (finer bases, more levels), the closest written"), std::string::npos) << fin.err;
  EXPECT_EQ(fin.err.find("rgbmesh: error: "), fin.err.rfind("rgbmesh: error: ")) << fin.err;  // one error line
  // A time budget the first fit already used: no attempt.
  const RunResult quick = run("fit --target " + hinge + " --base-faces 100 --sharp-angle 30 --retry-seconds 0 --out " +
                              path("q"));
  EXPECT_EQ(quick.code, 2) << quick.err;
  EXPECT_NE(quick.out.find("attempt 2 of 4: skipped: it would take about"), std::string::npos) << quick.out;
}

TEST_F(FitCli, OneSidedScansFitAsOpenSurfacesThatStopAtTheirBorder) {
  // Both distances within 0.5% RMS and 3% max of the diagonal, from the report.
  const auto expect_within = [&](const std::string& report, const std::string& what) {
    const std::size_t to = report.find("\"targets_to_surface\""), back = report.find("\"surface_to_target\"");
    EXPECT_LT(json_number(report, "rms_relative", to), 0.005) << what;
    EXPECT_LT(json_number(report, "max_relative", to), 0.03) << what;
    EXPECT_LT(json_number(report, "rms_relative", back), 0.005) << what;
    EXPECT_LT(json_number(report, "max_relative", back), 0.03) << what;
    EXPECT_GE(json_number(report, "boundary_loops", report.find("\"base\"")), 1) << what;  // open
  };
  // CGAL's hippo1 and hippo2: scans from one side. The advancing front's surface bridges what
  // the scan did not see (hippo1 decimated: surface-to-target RMS 1.1%, max 6.8% of the
  // diagonal); trimmed where no points lie, before the decimation, it stops at the scan's border
  // and is accepted at the first attempt (2026-12-06: hippo1 0.12% / 1.8% and 0.18% / 2.6%,
  // hippo2 0.12% / 3.0% and 0.24% / 2.8%). hippo2 has a lobe of 56 points held to the rest by a
  // single vertex once trimmed: it stays (the trim once dropped it, leaving targets 15% of the
  // diagonal from the surface).
  for (const char* name : {"hippo1", "hippo2"}) {
    const std::string scan = name;
    const RunResult hippo = run("fit --target " + public_data(scan + ".ply") + " --out " + path(scan) +
                                " --report " + path(scan + ".json"));
    ASSERT_EQ(hippo.code, 0) << hippo.err;
    EXPECT_NE(hippo.err.find("of the reconstructed surface's area where no points lie"), std::string::npos)
        << hippo.err;
    EXPECT_EQ(hippo.out.find("attempt 2 of"), std::string::npos) << scan << ": accepted at the first attempt";
    const std::string report = read_text(path(scan + ".json"));
    EXPECT_GT(json_number(report, "trimmed_area"), 0.01);
    expect_within(report, scan);
  }
  // Half of a sphere's points, with noise of 0.2% of the radius: an open cap, nothing beyond the
  // equator.
  {
    std::ofstream cloud(path("half.xyz"));
    UniformNumbers uniform(3);
    for (int n = 0; n < 5000;) {
      const double z = uniform(), phi = 2 * M_PI * uniform(), r = std::sqrt(1 - z * z);
      const double s = 1 + 0.002 * (uniform() + uniform() + uniform() - 1.5);
      cloud << r * std::cos(phi) * s << " " << r * std::sin(phi) * s << " " << z * s << "\n";
      ++n;
    }
  }
  const RunResult half = run("fit --target " + path("half.xyz") + " --out " + path("s") + " --report " + path("s.json"));
  ASSERT_EQ(half.code, 0) << half.err;
  expect_within(read_text(path("s.json")), "half sphere");
}

// Points in one plane (CGAL's point_set_2.xyz is such a 2D set) crashed CGAL's Poisson solver,
// whose Delaunay triangulation then has dimension 2. Now Poisson gives way with a note and the
// advancing front makes the flat sheet that such points sample. Points a hair off the plane make
// a 3D triangulation: whatever the outcome, no crash.
TEST_F(FitCli, PointsInOnePlaneAreAFlatSheetNotACrash) {
  for (const double lift : {0.0, 1e-9}) {
    std::ofstream cloud(path("plane.xyz"));
    UniformNumbers uniform(11);
    for (int n = 0; n < 3000; ++n) {
      const double x = uniform(), y = uniform();
      cloud << x << " " << y << " " << lift * uniform() << " 0 0 1\n";
    }
    cloud.close();
    const RunResult r = run("fit --target " + path("plane.xyz") + " --iterations 5 --no-retry --out " + path("p"));
    if (lift == 0.0) {
      EXPECT_EQ(r.code, 0) << r.err;
      EXPECT_NE(r.err.find("Poisson: the points lie in one plane"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("by advancing front"), std::string::npos) << r.err;
    } else {
      EXPECT_TRUE(r.code == 0 || r.code == 2) << r.code << ": " << r.err;
    }
  }
  // A 2D set of uneven density (as CGAL's point_set_2.xyz, which crashed CGAL's advancing front
  // in about half of the runs: its Delaunay triangulation has dimension 2): two dense discs
  // and a sparse strip between them, without normals. A sheet or a reason, every time.
  std::ofstream cloud(path("plane2.xyz"));
  UniformNumbers uniform(5);
  for (int n = 0; n < 2000; ++n) {
    const double r = 0.4 * std::sqrt(uniform()), a = 2 * M_PI * uniform();
    cloud << (n % 2 == 0 ? 0.0 : 2.0) + r * std::cos(a) << " " << r * std::sin(a) << " 0\n";
  }
  for (int n = 0; n < 60; ++n) cloud << 0.4 + 1.2 * uniform() << " " << 0.2 * (uniform() - 0.5) << " 0\n";
  cloud.close();
  for (int attempt = 0; attempt < 3; ++attempt) {
    const RunResult r = run("fit --target " + path("plane2.xyz") + " --iterations 5 --no-retry --out " + path("q"));
    EXPECT_TRUE(r.code == 0 || r.code == 2) << r.code << ": " << r.err;
  }
}

TEST_F(FitCli, PolygonTargetsAreRefusedLikeEverywhereElse) {
  // 3torus.off: quads of a genus-3 surface, once silently reconstructed from its vertices into
  // a genus-0 blob.
  const RunResult r = run("fit --target " + public_data("3torus.off") + " --out " + path("f"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--triangulate"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3torus.off: "), std::string::npos) << r.err;
  const RunResult t = run("fit --target " + public_data("3torus.off") + " --triangulate --iterations 5 --out " +
                          path("t") + " --report " + path("t.json"));
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_EQ(json_number(read_text(path("t.json")), "genus", read_text(path("t.json")).find("\"base\"")), 3);
}

TEST_F(FitCli, CloudsThatHungFinishWithAFitOrAReasonAndTooFewPointsAreRefused) {
  // CGAL's before_upsample.xyz (an open, creased sheet) and fin90_with_PCA_normals.xyz (a
  // folded CAD part with principal-direction normals) kept the surface mesher running for
  // hours. The first is an open surface: fitted open.
  const RunResult open = run("fit --target " + public_data("before_upsample.xyz") + " --out " + path("a") +
                             " --report " + path("a.json"));
  ASSERT_EQ(open.code, 0) << open.err;
  const std::string report = read_text(path("a.json"));
  EXPECT_NE(report.find("\"reconstruction\": \"advancing-front\""), std::string::npos) << report;
  EXPECT_EQ(json_number(report, "boundary_loops", report.find("\"base\"")), 1);
  const RunResult folded = run("fit --target " + public_data("fin90_with_PCA_normals.xyz") + " --no-retry --out " + path("b"));
  EXPECT_TRUE(folded.code == 0 || folded.code == 2) << folded.err;
  if (folded.code == 2) {
    EXPECT_NE(folded.err.find("of the diagonal"), std::string::npos) << folded.err;
  }
  // 49 points: no surface is determined between them.
  const RunResult sparse = run("fit --target " + public_data("points.xyz") + " --out " + path("c"));
  EXPECT_EQ(sparse.code, 2) << sparse.err;
  EXPECT_NE(sparse.err.find("too sparse to determine a surface"), std::string::npos) << sparse.err;
  EXPECT_NE(sparse.err.find("--base"), std::string::npos) << sparse.err;
}

TEST_F(FitCli, AStagePastTheMemoryCeilingStopsWithExitCode3NamingIt) {
  const std::string cloud = write_sphere_cloud("sphere.xyz", 60000);
  const RunResult r = run("--memory-limit 20M fit --target " + cloud + " --out " + path("f"));
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("more than the memory limit of 20 MB (--memory-limit)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rgbmesh: error: reconstructing a surface from 60,000 points"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rgbmesh::testing
