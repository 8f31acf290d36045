// The command-line tool, run as a user would: exit codes, messages, outputs, stage order.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <map>
#include <sstream>
#include <array>
#include <cstdint>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include "cli_fixture.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace fs = std::filesystem;

namespace {

using namespace rgbmesh::testing;

// Triangles as a set of triples rotated so that the smallest index comes first (orientation kept).
std::set<std::array<std::int32_t, 3>> oriented_triangle_set(
    const std::vector<std::array<std::int32_t, 3>>& tris) {
  std::set<std::array<std::int32_t, 3>> out;
  for (auto t : tris) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

TEST_F(Cli, DefaultJobWritesItsOutputs) {
  const RunResult r = run("--out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("out") + "/solution.pvd"));
  EXPECT_TRUE(fs::exists(path("out") + "/cycle_000.vtp"));
  EXPECT_NE(r.out.find("sphere-peak"), std::string::npos) << r.out;
}

TEST_F(Cli, AdaptWritesCyclesSeriesAndReport) {
  const RunResult r = run("adapt --problem sphere-peak --cycles 4 --out " + path("a") + " --report " + path("a/r.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  for (int c = 0; c < 4; ++c) {
    const std::string file = path("a") + "/cycle_00" + std::to_string(c) + ".vtp";
    VtpArrays a = read_vtp_arrays(file);
    EXPECT_GT(a.points, 0) << file;
    for (const char* name : {"solution", "exact_solution", "error", "level"}) EXPECT_EQ(a.point_arrays[name], 1) << name;
    for (const char* name : {"error_indicator", "marked", "level", "color"}) EXPECT_EQ(a.cell_arrays[name], 1) << name;
  }
  const std::string pvd = read_text(path("a") + "/solution.pvd");
  EXPECT_NE(pvd.find("cycle_003.vtp"), std::string::npos) << pvd;
  const std::string json = read_text(path("a/r.json"));
  for (const char* key : {"\"problem\": \"sphere-peak\"", "\"strategy\": \"adaptive\"", "\"cycles\": [", "\"error_h1\"",
                          "\"estimate\"", "\"dofs\"", "\"seconds\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
  // A problem without exact solution has no error fields.
  const RunResult g = run("adapt --mesh " + write_octahedron("octa.off") + " --problem gaussian --cycles 2 --out " +
                          path("g") + " --report " + path("g/r.json"));
  ASSERT_EQ(g.code, 0) << g.err;
  const std::string gjson = read_text(path("g/r.json"));
  EXPECT_EQ(gjson.find("error_h1"), std::string::npos) << gjson;
  EXPECT_EQ(read_vtp_arrays(path("g") + "/cycle_001.vtp").point_arrays.count("exact_solution"), 0u);
}

TEST_F(Cli, FitWritesTheFittedBaseTheLimitSurfaceAndAReport) {
  const std::string bunny = std::string(RGBMESH_DATA_DIR) + "/bunny.obj";
  const RunResult r = run("fit --target " + bunny + " --base-faces 600 --levels 2 --out " + path("f") + " --report " +
                          path("f/r.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto base = rgbmesh::read_mesh(path("f") + "/fitted_base.obj");
  EXPECT_NEAR(static_cast<double>(base.triangles.size()), 600.0, 20.0);
  VtpArrays limit = read_vtp_arrays(path("f") + "/limit_surface.vtp");
  EXPECT_EQ(limit.cells, static_cast<vtkIdType>(base.triangles.size() * 16));
  EXPECT_EQ(limit.cell_arrays["targets"], 1);
  EXPECT_EQ(limit.cell_arrays["rms_distance"], 1);
  const std::string report = read_text(path("f/r.json"));
  for (const char* key : {"\"iterations\": [", "\"rms\"", "\"max\"", "\"rms_relative\"", "\"max_relative\"", "\"seconds\""})
    EXPECT_NE(report.find(key), std::string::npos) << key;
  const double rel = std::stod(report.substr(report.find("\"rms_relative\": ") + 16));
  EXPECT_LT(rel, 0.003);
  // Bad arguments: exit code 2 and a message.
  for (const std::string& args : {"--target " + path("none.xyz"), "--target " + bunny + " --loss square",
                                 "--target " + bunny + " --levels 9"}) {
    const RunResult bad = run("fit " + args + " --out " + path("g"));
    EXPECT_EQ(bad.code, 2) << args << ": " << bad.err;
  }
}

TEST_F(Cli, AdaptRejectsBadArguments) {
  for (const char* args : {"--problem nope", "--strategy sometimes", "--theta 2", "--solver magic", "--geometry flat",
                           "--cycles 0"}) {
    const RunResult r = run(std::string("adapt --out ") + path("x") + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << args;
  }
}

// Points and a 3-component point array of a VTP file, read with VTK's own reader.
struct VtpPoints {
  std::vector<std::array<double, 3>> points, control, limit;
};
VtpPoints read_vtp_points(const std::string& file) {
  const vtkSmartPointer<vtkPolyData> pd = read_vtp(file);
  VtpPoints out;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i) {
    std::array<double, 3> p;
    pd->GetPoint(i, p.data());
    out.points.push_back(p);
  }
  for (auto [name, dst] : {std::pair{"control_point", &out.control}, std::pair{"limit", &out.limit}}) {
    vtkDataArray* a = pd->GetPointData()->GetArray(name);
    if (a == nullptr || a->GetNumberOfComponents() != 3) continue;
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
      std::array<double, 3> p;
      a->GetTuple(i, p.data());
      dst->push_back(p);
    }
  }
  return out;
}

TEST_F(Cli, VtkOutputCarriesControlPointsAndLimitPositions) {
  const std::string in = write_octahedron("octa.off");
  ASSERT_EQ(run("refine " + in + " " + path("c.vtp") + " --uniform 2 --ball 0.6,0,0,0.3,4").code, 0);
  ASSERT_EQ(run("refine " + in + " " + path("l.vtp") + " --uniform 2 --ball 0.6,0,0,0.3,4 --limit").code, 0);
  const VtpPoints c = read_vtp_points(path("c.vtp")), l = read_vtp_points(path("l.vtp"));
  ASSERT_GT(c.points.size(), 66u);
  ASSERT_EQ(c.control.size(), c.points.size());
  ASSERT_EQ(c.limit.size(), c.points.size());
  EXPECT_EQ(c.control, c.points);  // points are the control points...
  EXPECT_EQ(l.points, c.limit);    // ...or, with --limit, the limit positions
  EXPECT_EQ(l.limit, c.limit);
  // The octahedron's limit surface lies strictly inside it (|x| + |y| + |z| < 1) and its
  // control points are pulled towards the limit from outside that surface.
  int moved = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const auto& p = c.limit[i];
    EXPECT_LT(std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]), 1.0);
    if (c.limit[i] != c.control[i]) ++moved;
  }
  EXPECT_EQ(moved, static_cast<int>(c.points.size()));
}

TEST_F(Cli, GeometricToleranceRefinesUntilTheSurfaceIsResolved) {
  const std::string in = write_octahedron("octa.off");
  const RunResult coarse = run("refine " + in + " - --geometric-tol 0.01 --stats");
  const RunResult fine = run("refine " + in + " - --geometric-tol 0.001 --stats");
  ASSERT_EQ(coarse.code, 0) << coarse.err;
  ASSERT_EQ(fine.code, 0) << fine.err;
  const long t_coarse = json_int(last_line(coarse.out), "triangles"), t_fine = json_int(last_line(fine.out), "triangles");
  // A smooth surface: the deviation shrinks by 4 per level, so a 10x smaller tolerance needs
  // about 1.66 more levels, i.e. 10 times more triangles (between 4 and 16 times).
  EXPECT_GT(t_coarse, 8);
  EXPECT_GE(t_fine, 4 * t_coarse);
  EXPECT_LE(t_fine, 16 * t_coarse);
  const RunResult bad = run("refine " + in + " - --geometric-tol -1");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--geometric-tol"), std::string::npos) << bad.err;
}

TEST_F(Cli, InfoReportsTopology) {
  const RunResult r = run("info --json " + write_octahedron("octa.off"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_int(r.out, "vertices"), 6);
  EXPECT_EQ(json_int(r.out, "edges"), 12);
  EXPECT_EQ(json_int(r.out, "triangles"), 8);
  EXPECT_EQ(json_int(r.out, "boundary_loops"), 0);
  EXPECT_EQ(json_int(r.out, "euler_characteristic"), 2);
  EXPECT_EQ(json_int(r.out, "genus"), 0);
  EXPECT_NE(r.out.find("\"valence_histogram\": {\"4\": 6}"), std::string::npos) << r.out;
  const RunResult text = run("info " + path("octa.off"));
  ASSERT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("genus:                0"), std::string::npos) << text.out;
}

TEST_F(Cli, RefineAppliesStagesInOrderAndReportsStats) {
  const std::string in = write_octahedron("octa.off");
  RunResult r = run("refine " + in + " - --max-level 1 --uniform 3 --stats");
  ASSERT_EQ(r.code, 0) << r.err;
  std::string stats = last_line(r.out);
  EXPECT_EQ(json_int(stats, "triangles"), 8 * 4);
  EXPECT_EQ(json_int(stats, "max_level"), 1);
  r = run("refine " + in + " - --uniform 3 --max-level 1 --stats");
  ASSERT_EQ(r.code, 0) << r.err;
  stats = last_line(r.out);
  EXPECT_EQ(json_int(stats, "triangles"), 8 * 64);
  // A closed genus-0 mesh has V = T/2 + 2.
  EXPECT_EQ(json_int(stats, "vertices"), 8 * 64 / 2 + 2);
  EXPECT_EQ(json_int(stats, "splits"), 8 * 64 / 2 + 2 - 6);
  for (const char* key : {"\"refine_seconds\": ", "\"peak_rss_mb\": ", "\"removals\": 0"})
    EXPECT_NE(stats.find(key), std::string::npos) << key;
}

TEST_F(Cli, CoarsenAllAfterRandomWalkRestoresTheBaseMesh) {
  const std::string in = write_octahedron("octa.off");
  const RunResult r = run("refine " + in + " " + path("back.off") + " --random-walk 3000,17 --coarsen-all --stats");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string stats = last_line(r.out);
  EXPECT_GT(json_int(stats, "splits"), 500);
  EXPECT_EQ(json_int(stats, "splits"), json_int(stats, "removals"));
  const auto a = rgbmesh::read_mesh(in), b = rgbmesh::read_mesh(path("back.off"));
  // Base vertices keep their handles, so positions match one to one; triangle handles are
  // recycled through the free lists, so compare triangles as a set of oriented triples.
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(oriented_triangle_set(a.triangles), oriented_triangle_set(b.triangles));
  EXPECT_EQ(b.triangles.size(), a.triangles.size());
}

TEST_F(Cli, RandomWalksAreReproducible) {
  const std::string in = write_octahedron("octa.off");
  ASSERT_EQ(run("refine " + in + " " + path("a.vtp") + " --random-walk 2000,3").code, 0);
  ASSERT_EQ(run("refine " + in + " " + path("b.vtp") + " --random-walk 2000,3").code, 0);
  ASSERT_EQ(run("refine " + in + " " + path("c.vtp") + " --random-walk 2000,4").code, 0);
  const auto a = rgbmesh::read_mesh(path("a.vtp")), b = rgbmesh::read_mesh(path("b.vtp")),
             c = rgbmesh::read_mesh(path("c.vtp"));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.points, b.points);
  EXPECT_NE(a.points, c.points);
}

TEST_F(Cli, ConvertRoundTripsThroughEveryOutputFormat) {
  const std::string in = write_octahedron("octa.off");
  ASSERT_EQ(run("refine " + in + " " + path("r.vtp") + " --ball 1,0,0,0.5,3").code, 0);
  const auto ref = rgbmesh::read_mesh(path("r.vtp"));
  for (const char* ext : {"obj", "ply", "off", "stl", "vtu", "vtp"}) {
    const std::string out = path(std::string("c.") + ext);
    const RunResult r = run("convert " + path("r.vtp") + " " + out);
    ASSERT_EQ(r.code, 0) << ext << ": " << r.err;
    const auto back = rgbmesh::read_mesh(out);
    EXPECT_EQ(back.triangles.size(), ref.triangles.size()) << ext;
    EXPECT_EQ(back.points.size(), ref.points.size()) << ext;
  }
}

TEST_F(Cli, BadInputGivesExitCode2AndNamesTheProblem) {
  const std::string in = write_octahedron("octa.off");
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"info " + path("missing.obj"), "missing.obj"},
      {"refine " + in + " - --ball 1,2", "--ball"},
      {"refine " + in + " - --uniform x", "--uniform"},
      {"refine " + in + " - --max-edge -1", "--max-edge"},
      {"refine " + in + " - --random-walk 10", "--random-walk"},
      {"refine " + in + " " + path("out.xyz"), "unknown output format"},
      {"convert " + in, "OUT"},
      {"frobnicate", "frobnicate"},
  };
  for (const auto& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << "\nstderr: " << r.err;
  }
  EXPECT_FALSE(fs::exists(path("out.xyz")));
}

TEST_F(Cli, InvalidMeshesAreRejectedWithTheElement) {
  {
    std::ofstream f(path("nonmanifold.off"));
    f << "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
  }
  RunResult r = run("info " + path("nonmanifold.off"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nonmanifold.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("edge (0, 1)"), std::string::npos) << r.err;
  {
    std::ofstream f(path("quad.off"));
    f << "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  }
  r = run("info " + path("quad.off"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--triangulate"), std::string::npos) << r.err;
  r = run("info --json --triangulate " + path("quad.off"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_int(r.out, "triangles"), 2);
}

TEST_F(Cli, EverySubcommandHasHelp) {
  for (const std::string sub : {"", "info", "convert", "refine", "adapt", "fit"}) {
    const RunResult r = run(sub + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  EXPECT_NE(run("refine --help").out.find("--random-walk"), std::string::npos);
}

}  // namespace
